// libFuzzer harness: `masse sweep --collect`, which reads a study folder that workers, Slurm tasks or a user may have
// left in any state. The input is the folder, its files separated by lines "----": first study.json, then one part a
// case, whose first line is the case's status.txt (and run.log) and whose rest is its summary.json. The collection
// must end in InputError or in results (results.csv and the table); anything else is a finding. Plots are left out:
// they run gnuplot, which reads only what the collection made.

#include "FuzzInput.h"

#include "core/InputError.h"
#include "scene/output/AtomicFile.h"
#include "scene/study/StudyResults.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace
{
namespace fs = std::filesystem;

/// The input cut at every line "----".
std::vector<std::string_view> parts(std::string_view input)
{
    constexpr std::string_view separator = "\n----\n";
    std::vector<std::string_view> cut;
    std::size_t start = 0;
    for (std::size_t at = input.find(separator); at != std::string_view::npos; at = input.find(separator, start))
    {
        cut.push_back(input.substr(start, at - start));
        start = at + separator.size();
    }
    cut.push_back(input.substr(start));
    return cut;
}

void write(const fs::path& path, std::string_view text)
{
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(text.data(), std::streamsize(text.size()));
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const fs::path dir = masse::fuzz::workFolder() / "study";
    fs::remove_all(dir);
    fs::create_directories(dir);
    const std::vector<std::string_view> files = parts(std::string_view(reinterpret_cast<const char*>(data), size));
    write(dir / "study.json", files[0]);
    for (std::size_t i = 1; i < files.size(); ++i)
    {
        const fs::path folder = masse::scene::caseFolder(dir.string(), i - 1);
        fs::create_directories(folder);
        const std::size_t lineEnd = std::min(files[i].find('\n'), files[i].size());
        write(folder / "status.txt", files[i].substr(0, lineEnd));
        write(folder / "run.log", files[i].substr(0, lineEnd));
        write(folder / "summary.json", files[i].substr(std::min(lineEnd + 1, files[i].size())));
    }
    try
    {
        const masse::scene::StudyResults results = masse::scene::collectResults(dir.string());
        masse::scene::writeFileAtomically((dir / "results.csv").string(), masse::scene::resultsCsv(results));
        (void)masse::scene::resultsTable(results);
    }
    catch (const masse::InputError&)
    {
    }
    return 0;
}
