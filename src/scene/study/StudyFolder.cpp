#include "scene/study/StudyFolder.h"

#include "scene/json/JsonObject.h"
#include "scene/output/AtomicFile.h"
#include "scene/output/OutputFolder.h"

#include "core/InputError.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace masse::scene
{
namespace
{
namespace fs = std::filesystem;

nlohmann::json studyRecordJson(const Study& study)
{
    nlohmann::json parameters = nlohmann::json::array();
    for (const StudyParameter& p : study.parameters)
    {
        nlohmann::json keys = nlohmann::json::array();
        for (const StudyTarget& t : p.targets)
        {
            keys.push_back(t.key.text());
        }
        parameters.push_back({{"name", p.name}, {"unit", p.unit}, {"keys", keys}});
    }
    nlohmann::json outputs = nlohmann::json::array();
    for (const StudyOutput& o : study.outputs)
    {
        outputs.push_back({{"name", o.name}, {"path", o.path}, {"unit", o.unit}});
    }
    nlohmann::json cases = nlohmann::json::array();
    for (const std::vector<nlohmann::json>& values : study.cases)
    {
        cases.push_back(values);
    }
    return {{"name", study.name},       {"scene", study.scenePath}, {"design", study.design},
            {"parameters", parameters}, {"outputs", outputs},       {"cases", cases}};
}

/// What the study puts into a case's folder for its run: the scene, the run's log, the status it writes after.
const std::vector<std::string> caseFiles = {"scene.json", "run.log", "status.txt"};

std::string readText(const std::string& path)
{
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

} // namespace

std::string columnHeader(const std::string& name, const std::string& unit)
{
    return unit.empty() ? name : name + " [" + unit + "]";
}

std::string csvField(const std::string& text)
{
    if (text.find_first_of(",\"\n\r") == std::string::npos)
    {
        return text;
    }
    std::string quoted = "\"";
    for (char c : text)
    {
        quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    }
    return quoted + "\"";
}

std::string caseFolder(const std::string& dir, std::size_t index)
{
    char name[16];
    std::snprintf(name, sizeof(name), "%04zu", index);
    return (fs::path(dir) / "cases" / name).string();
}

void prepareStudyFolder(const Study& study, const std::string& dir)
{
    const nlohmann::json record = studyRecordJson(study);
    std::vector<std::string> scenes;
    for (std::size_t i = 0; i < study.cases.size(); ++i)
    {
        nlohmann::json scene = caseDocument(study, i);
        rebaseFilePaths(scene, fs::path(study.scenePath).parent_path().string(), caseFolder(dir, i));
        if (!scene.contains("name"))
        {
            scene["name"] = fs::path(study.scenePath).stem().string();
        }
        scenes.push_back(scene.dump(2) + "\n");
    }

    // Everything is checked before anything is written: a folder that is not this study stays untouched.
    if (fs::exists(dir))
    {
        if (!fs::is_directory(dir))
        {
            throw InputError("--out: '" + dir + "' exists and is not a folder");
        }
        const bool empty = fs::is_empty(dir);
        if (!empty && !fs::exists(fs::path(dir) / "study.json"))
        {
            throw InputError("--out: '" + dir + "' holds other files and no study.json: give a new or empty folder");
        }
        if (!empty)
        {
            nlohmann::json existing =
                nlohmann::json::parse(readText((fs::path(dir) / "study.json").string()), nullptr, false);
            // The same study may be resumed from another working folder: the scene's path may be written
            // differently, what matters is that every case's scene is the same (checked next).
            nlohmann::json mine = record;
            if (existing.is_object())
            {
                existing.erase("scene");
            }
            mine.erase("scene");
            if (existing != mine)
            {
                throw InputError("--out: '" + dir +
                                 "' holds another study (its parameters, values or outputs "
                                 "differ): give a new folder to start this one");
            }
            for (std::size_t i = 0; i < scenes.size(); ++i)
            {
                const std::string path = caseFolder(dir, i) + "/scene.json";
                if (fs::exists(path) && readText(path) != scenes[i])
                {
                    throw InputError("--out: " + path +
                                     " differs from the case's scene now (the base scene "
                                     "changed?): give a new folder, or remove the old one");
                }
            }
        }
    }

    // study.json first: a sweep interrupted while writing the cases finds its own study here and completes them.
    // A folder that cannot be made or written (a read-only file system) is bad input, refused before any case runs.
    std::error_code error;
    fs::create_directories(fs::path(dir) / "cases", error);
    if (error)
    {
        throw InputError("--out: '" + dir + "' cannot be written (" + error.message() + ")");
    }
    writeFileAtomically((fs::path(dir) / "study.json").string(), record.dump(2) + "\n");
    std::ostringstream manifest;
    manifest << "case,folder";
    for (const StudyParameter& p : study.parameters)
    {
        manifest << "," << csvField(columnHeader(p.name, p.unit));
    }
    manifest << "\n";
    for (std::size_t i = 0; i < study.cases.size(); ++i)
    {
        const std::string folder = caseFolder(dir, i);
        fs::create_directories(folder);
        if (!fs::exists(folder + "/scene.json"))
        {
            writeFileAtomically(folder + "/scene.json", scenes[i]);
        }
        // The case's run writes into this folder beside what the study puts there: the folder's manifest says those
        // are MaSSE's, so the run neither refuses them as the user's nor drops them when it replaces the folder.
        keepInOutputFolder(folder, caseFiles);
        manifest << i << "," << csvField(fs::path(folder).lexically_relative(dir).string());
        for (const nlohmann::json& value : study.cases[i])
        {
            manifest << "," << csvField(valueText(value));
        }
        manifest << "\n";
    }
    writeFileAtomically((fs::path(dir) / "cases.csv").string(), manifest.str());
}

StudyRecord readStudyRecord(const std::string& dir)
{
    const std::string path = (fs::path(dir) / "study.json").string();
    if (!fs::exists(path))
    {
        throw InputError("--collect: " + dir + " is not a study folder (no study.json; masse sweep STUDY --out " + dir +
                         " makes one)");
    }
    const nlohmann::json document = readJsonFile(path);
    StudyRecord record;
    try
    {
        record.name = document.at("name").get<std::string>();
        record.scene = document.at("scene").get<std::string>();
        for (const nlohmann::json& p : document.at("parameters"))
        {
            StudyParameter parameter;
            parameter.name = p.at("name").get<std::string>();
            parameter.unit = p.at("unit").get<std::string>();
            for (const nlohmann::json& key : p.at("keys"))
            {
                parameter.targets.push_back({parseJsonPath(key.get<std::string>()), 1, 0});
            }
            record.parameters.push_back(std::move(parameter));
        }
        for (const nlohmann::json& o : document.at("outputs"))
        {
            record.outputs.push_back(
                {o.at("name").get<std::string>(), o.at("path").get<std::string>(), o.at("unit").get<std::string>()});
        }
        for (const nlohmann::json& values : document.at("cases"))
        {
            record.cases.push_back(values.get<std::vector<nlohmann::json>>());
        }
    }
    catch (const nlohmann::json::exception& e)
    {
        throw InputError(path + ": not a study record written by masse sweep (" + e.what() + ")");
    }
    // Every reader of the record indexes a case's values by parameter.
    for (std::size_t i = 0; i < record.cases.size(); ++i)
    {
        if (record.cases[i].size() != record.parameters.size())
        {
            throw InputError(path + ": cases[" + std::to_string(i) + "] has " + std::to_string(record.cases[i].size()) +
                             " value(s) for " + std::to_string(record.parameters.size()) +
                             " parameter(s); not a study record written by masse sweep");
        }
    }
    return record;
}

bool isRegularFile(const std::string& path)
{
    std::error_code error;
    return std::filesystem::is_regular_file(std::filesystem::status(path, error));
}

CaseStatus readCaseStatus(const std::string& caseDir)
{
    CaseStatus status;
    if (!isRegularFile(caseDir + "/status.txt"))
    {
        return status;
    }
    std::ifstream in(caseDir + "/status.txt");
    if (!in)
    {
        return status;
    }
    std::string line;
    bool haveCode = false;
    while (std::getline(in, line))
    {
        const std::size_t equals = line.find('=');
        const std::string key = line.substr(0, equals);
        const std::string value = equals == std::string::npos ? "" : line.substr(equals + 1);
        try
        {
            if (key == "exit_code")
            {
                status.exitCode = std::stoi(value);
                haveCode = true;
            }
            else if (key == "wall_seconds")
            {
                status.wallSeconds = std::stod(value);
            }
        }
        catch (const std::exception&)
        {
            // A status that cannot be read counts as no status: the case runs again.
        }
    }
    status.finished = haveCode;
    return status;
}

void writeCaseStatus(const std::string& caseDir, int exitCode, double wallSeconds)
{
    char text[96];
    std::snprintf(text, sizeof(text), "exit_code=%d\nwall_seconds=%.6f\n", exitCode, wallSeconds);
    writeFileAtomically(caseDir + "/status.txt", text);
}

std::vector<std::size_t> casesToRun(const std::string& dir, std::size_t caseCount, bool retryFailed)
{
    std::vector<std::size_t> pending;
    for (std::size_t i = 0; i < caseCount; ++i)
    {
        const CaseStatus status = readCaseStatus(caseFolder(dir, i));
        if (!status.finished || (retryFailed && status.exitCode != 0))
        {
            pending.push_back(i);
        }
    }
    return pending;
}

void clearCaseOutputs(const std::string& caseDir)
{
    removeListedOutputs(caseDir, {"scene.json"});
}

std::string lastLogLine(const std::string& caseDir)
{
    if (!isRegularFile(caseDir + "/run.log"))
    {
        return "";
    }
    std::ifstream in(caseDir + "/run.log");
    std::string line;
    std::string last;
    while (std::getline(in, line))
    {
        if (line.find_first_not_of(" \t\r") != std::string::npos)
        {
            last = line;
        }
    }
    if (last.rfind("masse: ", 0) == 0)
    {
        last = last.substr(7);
    }
    return last;
}
} // namespace masse::scene
