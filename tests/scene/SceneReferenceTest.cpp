// data/scenes/README.md documents every key the scene readers accept: this test reads the readers' own source (every
// key they ask a JSON object for) and the document, and names each key the document lacks. The readers are every file
// of src/scene that reads a scene's or a material's JSON: the scene file itself, material files, the `forming` section
// (FormingSpec.cpp), each report (src/scene/reports/), each obstacle shape (src/scene/shapes/), the `expect` block
// (Regression.cpp) and each material law (src/core/material/*Law.cpp, which reads its keys through the material
// reader). The registries are checked against their tables too: each registered report has its row in the `report`
// table, each integrator its name in the `integrator` table, each shape its name in the `obstacles[]` table, each
// material law its name in the material-file table.
// Study files have their own reference (data/studies/README.md).

#include "scene/reports/ReportRegistry.h"
#include "scene/shapes/ShapeRegistry.h"

#include "core/contact/Contact.h"
#include "core/integrate/Integrator.h"
#include "core/lattice/Lattice.h"
#include "core/material/MaterialLaw.h"
#include "core/material/ViscoelasticSprings.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

namespace
{
const std::string source = MASSE_SOURCE_DIR;

std::string readText(const std::string& path)
{
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// Every key a reader asks for: the first string argument of JsonObject's readers (o.number("dt", ...),
/// o.object("heat"), ...) and of the readers' own helpers (celsius(o, "key"), fraction(o, "key"), optional("key"),
/// plausible::point(o, "key") and its kin, prismLength(o, "key")).
std::set<std::string> keysAskedFor(const std::string& code)
{
    static const std::regex call(
        R"re((?:\.|->)(?:number|positive|string|boolean|integer|vec3|vec3List|choice|object|objects|raw|numbers)\(\s*"([A-Za-z_0-9]+)")re");
    static const std::regex helper(
        R"re((?:celsius|fraction|point|gravity|thickness|density|prismLength)\(\s*[A-Za-z_*]+,\s*"([A-Za-z_0-9]+)"|optional\(\s*"([A-Za-z_0-9]+)")re");
    std::set<std::string> keys;
    for (auto it = std::sregex_iterator(code.begin(), code.end(), call); it != std::sregex_iterator(); ++it)
    {
        keys.insert((*it)[1]);
    }
    for (auto it = std::sregex_iterator(code.begin(), code.end(), helper); it != std::sregex_iterator(); ++it)
    {
        keys.insert((*it)[1].matched ? (*it)[1].str() : (*it)[2].str());
    }
    return keys;
}

/// The values of the script's "action" choice list: choice("action", "grab", {"grab", "release", ...}).
std::set<std::string> actionNames(const std::string& code)
{
    static const std::regex list(R"re(choice\(\s*"action",\s*"[a-z]+",\s*\{([^}]*)\})re");
    static const std::regex name(R"re("([a-z_]+)")re");
    std::set<std::string> names;
    std::smatch m;
    if (std::regex_search(code, m, list))
    {
        const std::string inner = m[1];
        for (auto it = std::sregex_iterator(inner.begin(), inner.end(), name); it != std::sregex_iterator(); ++it)
        {
            names.insert((*it)[1]);
        }
    }
    return names;
}

/// The rows of the document's section whose heading is `heading` (the lines from it to the next heading).
std::string section(const std::string& document, const std::string& heading)
{
    const std::size_t start = document.find("\n" + heading + "\n");
    if (start == std::string::npos)
    {
        return "";
    }
    const std::size_t end = document.find("\n#", start + 1);
    return document.substr(start, end == std::string::npos ? std::string::npos : end - start);
}

/// The key appears in the document in code quotes, alone or as the last part of a dotted path (`heaters[].power`).
bool documented(const std::string& document, const std::string& key)
{
    const std::regex quoted("`([A-Za-z_0-9\\[\\]]+\\.)*" + key + "`");
    return std::regex_search(document, quoted);
}
} // namespace

TEST(SceneReference, EveryKeyTheReadersAcceptIsDocumented)
{
    const std::string document = readText(source + "/data/scenes/README.md");
    ASSERT_FALSE(document.empty());
    int checked = 0;
    std::vector<std::string> readers = {"/src/scene/SceneFile.cpp", "/src/scene/MaterialFile.cpp",
                                        "/src/scene/FormingSpec.cpp", "/src/scene/compare/Regression.cpp"};
    std::string reportReaders;
    for (const auto& file : std::filesystem::directory_iterator(source + "/src/scene/reports"))
    {
        if (file.path().extension() == ".cpp")
        {
            readers.push_back("/src/scene/reports/" + file.path().filename().string());
            reportReaders += readText(file.path().string());
        }
    }
    EXPECT_GT(keysAskedFor(reportReaders).size(), 5u); // the pattern still finds the reports' keys
    std::string shapeReaders;
    for (const auto& file : std::filesystem::directory_iterator(source + "/src/scene/shapes"))
    {
        if (file.path().extension() == ".cpp")
        {
            readers.push_back("/src/scene/shapes/" + file.path().filename().string());
            shapeReaders += readText(file.path().string());
        }
    }
    EXPECT_GT(keysAskedFor(shapeReaders).size(), 6u); // the pattern still finds the shapes' keys
    std::string lawReaders;
    for (const auto& file : std::filesystem::directory_iterator(source + "/src/core/material"))
    {
        const std::string name = file.path().filename().string();
        if (name.size() > 7 && name.compare(name.size() - 7, 7, "Law.cpp") == 0)
        {
            readers.push_back("/src/core/material/" + name);
            lawReaders += readText(file.path().string());
        }
    }
    EXPECT_GE(keysAskedFor(lawReaders).size(), 7u); // the pattern still finds the laws' keys
    for (const std::string& reader : readers)
    {
        const std::set<std::string> keys = keysAskedFor(readText(source + reader));
        if (reader.rfind("/src/scene/reports/", 0) != 0 && reader.rfind("/src/scene/shapes/", 0) != 0 &&
            reader.rfind("/src/core/material/", 0) != 0)
        {
            EXPECT_FALSE(keys.empty()) << reader; // the pattern still finds the reader's keys
        }
        for (const std::string& key : keys)
        {
            EXPECT_TRUE(documented(document, key))
                << "data/scenes/README.md lacks `" << key << "` (read in " << reader << ")";
            ++checked;
        }
    }
    EXPECT_GT(checked, 100);
    const std::set<std::string> actions = actionNames(readText(source + "/src/scene/SceneFile.cpp"));
    EXPECT_EQ(actions.size(), 11u);
    for (const std::string& action : actions)
    {
        EXPECT_TRUE(documented(document, action)) << "data/scenes/README.md lacks the action `" << action << "`";
    }
}

// A report is registered in one table (src/scene/reports/ReportRegistry.cpp) and described in one: each registered
// key has its row in the `report` table, whatever its reader asks for.
TEST(SceneReference, EveryRegisteredReportHasARowInTheReportTable)
{
    const std::string table = section(readText(source + "/data/scenes/README.md"), "## `report`");
    ASSERT_FALSE(table.empty()) << "data/scenes/README.md has no `report` section";
    int keyed = 0;
    for (const masse::scene::ReportEntry* report : masse::scene::reports())
    {
        if (report->key.empty())
        {
            continue; // made without a key: described with summary.json's values
        }
        const std::string key(report->key);
        EXPECT_NE(table.find("\n| `" + key + "` |"), std::string::npos)
            << "data/scenes/README.md's `report` table lacks a row for the registered report `" << key << "`";
        ++keyed;
    }
    EXPECT_GE(keyed, 6);
}

// The `integrator` table's `type` row names every registered integrator.
namespace
{
/// Checks that the `key` row of the table under `heading` in data/scenes/README.md names each of `names` (a
/// registry's), in backquotes.
void expectRowNames(const std::string& heading, const std::string& key, const std::vector<std::string_view>& names)
{
    const std::string table = section(readText(source + "/data/scenes/README.md"), heading);
    const std::size_t row = table.find("\n| `" + key + "` |");
    ASSERT_NE(row, std::string::npos) << "data/scenes/README.md's table under " << heading << " has no `" << key
                                      << "` row";
    const std::string cells = table.substr(row, table.find('\n', row + 1) - row);
    for (const std::string_view name : names)
    {
        std::string quoted = "`";
        quoted.append(name).append("`");
        EXPECT_NE(cells.find(quoted), std::string::npos)
            << "data/scenes/README.md's `" << key << "` row under " << heading << " lacks " << quoted;
    }
}
} // namespace

TEST(SceneReference, EveryRegisteredIntegratorIsInTheIntegratorTable)
{
    std::vector<std::string_view> names;
    for (const masse::IntegratorEntry& integrator : masse::integrators())
    {
        names.push_back(integrator.name);
    }
    expectRowNames("## `integrator`", "type", names);
}

// A structure is registered in one table (structureTable, src/core/lattice/Lattice.h).
TEST(SceneReference, EveryRegisteredStructureIsInTheSheetTable)
{
    std::vector<std::string_view> names;
    for (const auto& entry : masse::structureTable)
    {
        names.push_back(entry.name);
    }
    expectRowNames("## `sheet`", "structure", names);
}

// The contact responses are registered in one table (contactResponseTable, core/contact/Contact.h).
TEST(SceneReference, EveryContactResponseIsInTheContactTable)
{
    std::vector<std::string_view> names;
    for (const auto& entry : masse::contactResponseTable)
    {
        names.push_back(entry.name);
    }
    expectRowNames("## `contact`", "response", names);
}

// The spring models' names come from one table (springModelNames, core/material/ViscoelasticSprings.h).
TEST(SceneReference, EverySpringModelIsInTheMaterialTable)
{
    const std::vector<std::string> models = masse::springModelNames();
    EXPECT_GE(models.size(), 3u);
    expectRowNames("## `material`", "spring_model", std::vector<std::string_view>(models.begin(), models.end()));
}

// A shape is registered in one table (src/scene/shapes/ShapeRegistry.cpp): the `obstacles[]` table's `type` row names
// every registered shape.
TEST(SceneReference, EveryRegisteredShapeIsInTheObstaclesTable)
{
    std::vector<std::string_view> names;
    for (const masse::scene::ShapeEntry* shape : masse::scene::shapes())
    {
        names.push_back(shape->name);
    }
    EXPECT_GE(names.size(), 4u);
    expectRowNames("## `obstacles[]`", "type", names);
}

// A material law is registered in one table (src/core/material/MaterialLaw.cpp): the material-file table's `law` row
// names every registered law.
TEST(SceneReference, EveryRegisteredMaterialLawIsInTheMaterialFileTable)
{
    std::vector<std::string_view> names;
    for (const masse::MaterialLawEntry* entry : masse::materialLaws())
    {
        names.push_back(entry->name);
    }
    expectRowNames("### Material files (`data/materials/*.json`, or `material.properties`)", "law", names);
}

// A key has one row in its section's table: two rows for one key can disagree (obstacles[].temperature_c once had a
// default of "none" in one row and "the air's" in the other).
TEST(SceneReference, EachKeyHasOneRowInItsSection)
{
    std::istringstream document(readText(source + "/data/scenes/README.md"));
    static const std::regex row(R"re(^\| (`[^|]*`) \|)re");
    std::string section;
    std::set<std::string> keys;
    std::string line;
    int rows = 0;
    while (std::getline(document, line))
    {
        if (line.rfind("#", 0) == 0)
        {
            section = line;
            keys.clear();
            continue;
        }
        std::smatch m;
        if (std::regex_search(line, m, row))
        {
            EXPECT_TRUE(keys.insert(m[1]).second) << section << ": " << m[1] << " has two rows";
            ++rows;
        }
    }
    EXPECT_GT(rows, 100);
}
