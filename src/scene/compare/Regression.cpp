#include "scene/compare/Regression.h"

#include "scene/SceneFile.h"
#include "scene/json/JsonObject.h"
#include "scene/json/JsonText.h"
#include "scene/output/AtomicFile.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#ifndef MASSE_BUILD_TYPE
#define MASSE_BUILD_TYPE "unknown"
#endif

namespace masse::scene
{
namespace
{
/// Six significant digits: enough to tell an expectation from a result, short enough to read.
std::string format(Real value)
{
    return formatNumber("%.6g", value);
}

std::string formatVec(const nlohmann::json& v)
{
    return "[" + format(v[0].get<Real>()) + ", " + format(v[1].get<Real>()) + ", " + format(v[2].get<Real>()) + "]";
}

/// Runs a scene to its end with no progress display and no files.
RunResult runQuietly(Scene& scene)
{
    RunOptions options;
    options.showProgress = false;
    std::ostringstream quiet;
    return runScene(scene, options, quiet);
}

/// The "expect" block of a scene file (with "extends" merged), as JSON.
nlohmann::json expectations(const std::string& path)
{
    const nlohmann::json document = readSceneDocument(path);
    if (!document.contains("expect"))
    {
        throw InputError(path + ": expect: a regression scene needs an \"expect\" block");
    }
    return document["expect"];
}

void checkEvents(const JsonObject& expect, const Scene& scene, std::vector<Check>& checks)
{
    Real previous = -std::numeric_limits<Real>::infinity();
    const bool inOrder = expect.boolean("in_order", true);
    bool ordered = true;
    for (const JsonObject& e : expect.objects("events"))
    {
        const std::string name = e.string("name");
        const std::string object = e.string("object");
        const Real expected = e.number("sim_time");
        const Real tolerance = e.number("tolerance", 0.03, 0.0);
        e.string("comment", ""); // why this is expected (an analytic value, say)
        e.finish();
        const Real actual = scene.eventTime(name, object);
        Check check;
        check.what = name + " " + object;
        check.expected = format(expected) + " s +- " + format(tolerance);
        if (actual < 0)
        {
            check.actual = "never";
            check.difference = "-";
        }
        else
        {
            check.actual = format(actual) + " s";
            check.difference = format(actual - expected) + " s";
            check.passed = std::abs(actual - expected) <= tolerance;
            ordered = ordered && actual >= previous;
            previous = actual;
        }
        checks.push_back(check);
    }
    if (inOrder && !checks.empty())
    {
        Check check;
        check.what = "events in order";
        check.expected = "yes";
        check.actual = ordered ? "yes" : "no";
        check.difference = "-";
        check.passed = ordered;
        checks.push_back(check);
    }
}

void checkFinal(const JsonObject& final, const nlohmann::json& summary, std::vector<Check>& checks)
{
    const nlohmann::json& actual = summary["final"];
    // Bounds on any number of the summary's "final" block, by its dotted path ("thickness.min_ratio").
    for (const std::string& key : final.keys())
    {
        if (key == "bbox_min" || key == "bbox_max" || key == "state_hash")
        {
            continue;
        }
        const JsonObject bound = *final.object(key);
        const Real min = bound.number("min", -std::numeric_limits<Real>::infinity());
        const Real max = bound.number("max", std::numeric_limits<Real>::infinity());
        bound.finish();
        const nlohmann::json* value = &actual;
        std::size_t start = 0;
        while (value && start <= key.size())
        {
            const std::size_t dot = std::min(key.find('.', start), key.size());
            const std::string part = key.substr(start, dot - start);
            value = value->is_object() && value->contains(part) ? &(*value)[part] : nullptr;
            start = dot + 1;
        }
        if (!value || !value->is_number())
        {
            final.fail(key, "the summary has no number at final." + key);
        }
        const Real got = value->get<Real>();
        const std::string expected = std::isinf(min)   ? "<= " + format(max)
                                     : std::isinf(max) ? ">= " + format(min)
                                                       : "in [" + format(min) + ", " + format(max) + "]";
        checks.push_back(
            {key, expected, format(got), got < min ? format(got - min) : format(got - max), got >= min && got <= max});
    }
    for (const char* key : {"bbox_min", "bbox_max"})
    {
        if (auto box = final.object(key))
        {
            const Vec3 expected = box->vec3("value");
            const Real tolerance = box->number("tolerance", 0.01, 0.0);
            box->finish();
            const nlohmann::json& v = actual[key];
            const Vec3 got(v[0].get<Real>(), v[1].get<Real>(), v[2].get<Real>());
            const Real difference = (got - expected).cwiseAbs().maxCoeff();
            checks.push_back(
                {key, formatVec(nlohmann::json{expected.x(), expected.y(), expected.z()}) + " +- " + format(tolerance),
                 formatVec(v), format(difference), difference <= tolerance});
        }
    }
    if (auto hashes = final.object("state_hash"))
    {
        const std::string buildType = MASSE_BUILD_TYPE;
        if (hashes->has(buildType))
        {
            const std::string expected = hashes->string(buildType);
            const std::string got = actual["state_hash"].get<std::string>();
            checks.push_back(
                {"state hash (" + buildType + ")", expected, got, got == expected ? "0" : "differs", got == expected});
        }
        // Hashes of other build types are not comparable with this build: read them so finish() accepts them.
        for (const char* other : {"Release", "Debug", "RelWithDebInfo", "MinSizeRel"})
        {
            hashes->raw(other);
        }
        hashes->finish();
    }
    final.finish();
}
} // namespace

bool RegressionResult::passed() const
{
    return !checks.empty() && std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.passed; });
}

RegressionResult runRegression(const std::string& path, const std::vector<KeyOverride>& overrides,
                               const EngineSettings& engine)
{
    const nlohmann::json expect = expectations(path);
    SceneSpec spec = loadScene(path, overrides);
    spec.engine = engine;
    Scene scene(spec);
    const RunResult run = runQuietly(scene);

    RegressionResult result;
    result.file = path;
    result.scene = spec.name;
    result.wallSeconds = run.summary["wall_seconds"].get<Real>();
    try
    {
        const JsonObject e(expect, "expect");
        checkEvents(e, scene, result.checks);
        if (auto final = e.object("final"))
        {
            checkFinal(*final, run.summary, result.checks);
        }
        e.finish();
    }
    catch (const InputError& error)
    {
        throw InputError(path + ": " + error.what());
    }
    return result;
}

void recordRegression(const std::string& path, const EngineSettings& engine)
{
    const nlohmann::json document = readJsonFile(path);
    SceneSpec spec = loadScene(path);
    spec.engine = engine;
    Scene scene(spec);
    const RunResult run = runQuietly(scene);

    nlohmann::json expect = document.value("expect", nlohmann::json::object());
    nlohmann::json events = nlohmann::json::array();
    for (const SceneEvent& e : scene.events())
    {
        // Rounded to the microsecond: the tolerance, not the digits, says how exact it must be.
        nlohmann::json entry = {{"name", e.name},
                                {"object", e.object},
                                {"sim_time", std::round(e.simTime * 1e6) / 1e6},
                                {"tolerance", 0.03}};
        if (expect.contains("events"))
        {
            for (const nlohmann::json& old : expect["events"])
            {
                if (old.value("name", "") == e.name && old.value("object", "") == e.object)
                {
                    entry["tolerance"] = old.value("tolerance", 0.03);
                    // An expectation with a comment is reasoned (an analytic time, say): keep its value.
                    if (old.contains("comment"))
                    {
                        entry["comment"] = old["comment"];
                        entry["sim_time"] = old["sim_time"];
                    }
                }
            }
        }
        events.push_back(entry);
    }
    expect["events"] = events;
    expect["final"]["state_hash"][MASSE_BUILD_TYPE] = run.summary["final"]["state_hash"];
    // Only the expect block is rewritten: the author's comments and layout elsewhere stay as they were.
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    writeFileAtomically(path, withTopLevelValue(text.str(), "expect", expect));
}

std::vector<std::string> regressionFiles(const std::string& path)
{
    std::vector<std::string> files;
    if (std::filesystem::is_directory(path))
    {
        for (const auto& entry : std::filesystem::directory_iterator(path))
        {
            if (entry.path().extension() == ".json")
            {
                files.push_back(entry.path().string());
            }
        }
        std::sort(files.begin(), files.end());
    }
    else if (std::filesystem::is_regular_file(path))
    {
        files.push_back(path);
    }
    else
    {
        throw InputError(path + ": no such file or folder");
    }
    return files;
}

std::string regressionTable(const std::vector<RegressionResult>& results)
{
    std::ostringstream out;
    char line[400];
    std::snprintf(line, sizeof(line), "%-26s %-24s %-28s %-28s %-12s %s\n", "scene", "check", "expected", "actual",
                  "difference", "result");
    out << line;
    for (const RegressionResult& r : results)
    {
        for (const Check& c : r.checks)
        {
            std::snprintf(line, sizeof(line), "%-26s %-24s %-28s %-28s %-12s %s\n", r.scene.c_str(), c.what.c_str(),
                          c.expected.c_str(), c.actual.c_str(), c.difference.c_str(), c.passed ? "pass" : "FAIL");
            out << line;
        }
    }
    return out.str();
}
} // namespace masse::scene
