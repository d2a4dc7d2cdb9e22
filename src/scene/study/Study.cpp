#include "scene/study/Study.h"
#include "scene/study/StudyDesign.h"

#include "scene/Runner.h"
#include "scene/Scene.h"
#include "scene/SceneFile.h"
#include "scene/json/JsonObject.h"

#include "core/InputError.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>

namespace masse::scene
{
namespace
{
constexpr std::size_t maxCases = 100000;

bool endsWith(const std::string& text, const std::string& tail)
{
    return text.size() >= tail.size() && text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
}

StudyTarget readTarget(const nlohmann::json& entry, const std::string& where)
{
    StudyTarget target;
    try
    {
        if (entry.is_string())
        {
            target.key = parseJsonPath(entry.get<std::string>());
            return target;
        }
        const JsonObject o(entry, where);
        target.key = parseJsonPath(o.string("key"));
        target.scale = o.number("scale", 1.0);
        target.offset = o.number("offset", 0.0);
        o.finish();
        return target;
    }
    catch (const InputError& e)
    {
        throw InputError(where + ": " + e.what());
    }
}

std::vector<nlohmann::json> readRangeValues(const JsonObject& range, bool forSampling, StudyRange& bounds)
{
    bounds.min = range.number("min");
    bounds.max = range.number("max");
    bounds.integer = range.boolean("integer", false);
    std::vector<nlohmann::json> values;
    if (forSampling)
    {
        if (range.has("count") || range.has("step"))
        {
            range.fail(range.has("count") ? "count" : "step",
                       "not used by a Latin hypercube (its \"samples\" sets how many values)");
        }
        if (!(bounds.max > bounds.min))
        {
            range.fail("max", "empty range: max must be above min (min " + valueText(bounds.min) + ", max " +
                                  valueText(bounds.max) + ")");
        }
        range.finish();
        return values;
    }
    if (bounds.max < bounds.min)
    {
        range.fail("max", "empty range: max " + valueText(bounds.max) + " is below min " + valueText(bounds.min));
    }
    if (range.has("count") == range.has("step"))
    {
        range.fail("count", "give either count (values from min to max inclusive) or step");
    }
    if (range.has("count"))
    {
        const int count = range.integer("count", 0, -1000000, 1000000);
        if (count < 1)
        {
            range.fail("count", "empty range: count must be >= 1 (got " + std::to_string(count) + ")");
        }
        if (count > 1 && bounds.max == bounds.min)
        {
            range.fail("max", "empty range: min and max are equal, so " + std::to_string(count) +
                                  " values would all be the same");
        }
        values = countValues(bounds, std::size_t(count));
    }
    else
    {
        const Real step = range.number("step");
        if (!(step > 0))
        {
            range.fail("step", "must be > 0 (got " + valueText(step) + ")");
        }
        values = stepValues(bounds, step);
    }
    range.finish();
    return values;
}

StudyOutput readOutput(const nlohmann::json& entry, const std::string& where)
{
    StudyOutput output;
    if (entry.is_string())
    {
        output.path = entry.get<std::string>();
        output.name = output.path;
    }
    else
    {
        const JsonObject o(entry, where);
        output.path = o.string("path");
        output.name = o.string("name", output.path);
        output.unit = o.string("unit", "");
        o.finish();
        if (!o.has("unit"))
        {
            output.unit = summaryUnit(output.path);
        }
        if (output.name.empty())
        {
            throw InputError(where + ".name: must not be empty");
        }
        return output;
    }
    output.unit = summaryUnit(output.path);
    return output;
}

/// Whether `path` is the summary value `added` names or lies inside it (`webbing.largest[0].masses` in `webbing`).
bool inside(const JsonPath& path, const std::string& added)
{
    const JsonPath prefix = parseJsonPath(added);
    if (prefix.steps.size() > path.steps.size())
    {
        return false;
    }
    for (std::size_t k = 0; k < prefix.steps.size(); ++k)
    {
        const JsonPathStep& a = prefix.steps[k];
        const JsonPathStep& b = path.steps[k];
        if (a.isIndex != b.isIndex || a.key != b.key || a.index != b.index)
        {
            return false;
        }
    }
    return true;
}

/// Throws InputError naming `where` when the summary has no value at the output's path. The values a run adds as it
/// runs (`added`, summaryKeysAddedByTheRun) are taken on trust: the summary of a scene that has not run lacks them.
void checkOutputPath(const StudyOutput& output, const nlohmann::json& summary, const std::vector<std::string>& added,
                     const std::string& where)
{
    if (output.path.rfind("event:", 0) == 0)
    {
        const std::string event = output.path.substr(6);
        if (event.empty() || event.front() == ':' || event.back() == ':' ||
            std::count(event.begin(), event.end(), ':') > 1)
        {
            throw InputError(where + ": " + output.path +
                             ": expected event:NAME or event:NAME:OBJECT, such as "
                             "event:contact:mould");
        }
        return;
    }
    JsonPath path;
    try
    {
        path = parseJsonPath(output.path);
    }
    catch (const InputError& e)
    {
        throw InputError(where + ": " + e.what());
    }
    if (std::any_of(added.begin(), added.end(), [&](const std::string& key) { return inside(path, key); }))
    {
        return;
    }
    // Walk down as far as the summary goes and say what the last object reached holds.
    const nlohmann::json* at = &summary;
    JsonPath walked;
    for (const JsonPathStep& step : path.steps)
    {
        walked.steps.push_back(step);
        const nlohmann::json* next = findAt(summary, walked);
        if (!next)
        {
            std::string holds;
            if (at->is_object())
            {
                for (const auto& item : at->items())
                {
                    holds += (holds.empty() ? "" : ", ") + item.key();
                }
                holds = " (it holds " + holds + ")";
            }
            else if (at->is_array())
            {
                holds = " (a list of " + std::to_string(at->size()) + ")";
            }
            walked.steps.pop_back();
            const std::string reached = walked.steps.empty() ? std::string("summary.json") : walked.text();
            const std::string missing = step.isIndex ? "[" + std::to_string(step.index) + "]" : "'" + step.key + "'";
            throw InputError(where + ": " + output.path + ": the scene's summary.json has no such value: " + reached +
                             " has no " + missing + holds);
        }
        at = next;
    }
    if (at->is_object() || at->is_array())
    {
        throw InputError(where + ": " + output.path + ": is " + (at->is_object() ? "an object" : "a list") +
                         ", not one value (name one of its parts, such as " + output.path +
                         (at->is_object() && !at->empty() ? "." + at->items().begin().key() : "[0]") + ")");
    }
}

nlohmann::json targetValue(const nlohmann::json& value, const StudyTarget& target)
{
    if (target.scale == 1 && target.offset == 0)
    {
        return value;
    }
    const double x = value.get<double>() * target.scale + target.offset;
    if (value.is_number_integer() && x == std::floor(x) && std::abs(x) < 9e15)
    {
        return std::int64_t(x);
    }
    return x;
}
} // namespace

std::string valueText(const nlohmann::json& value)
{
    if (value.is_number_float())
    {
        char text[32];
        const auto result = std::to_chars(text, text + sizeof(text), value.get<double>());
        return std::string(text, result.ptr);
    }
    if (value.is_string())
    {
        return value.get<std::string>();
    }
    return value.dump();
}

std::string summaryUnit(const std::string& path)
{
    if (path.rfind("event:", 0) == 0 || endsWith(path, "sim_seconds") || endsWith(path, "wall_seconds") ||
        endsWith(path, "sim_time") || endsWith(path, "wall_time") || path == "dt")
    {
        return "s";
    }
    if (path == "realtime_factor" || path == "runner_overhead" || endsWith(path, "ratio"))
    {
        return "1";
    }
    if (path.rfind("final.temperature_c", 0) == 0)
    {
        return "C";
    }
    if (path == "final.kinetic_energy")
    {
        return "J";
    }
    if (path.rfind("final.max_penetration", 0) == 0 || path.rfind("final.bbox_", 0) == 0 ||
        path.rfind("final.thickness.min_position", 0) == 0 || path == "final.thickness.min" ||
        path == "final.thickness.initial" || path.rfind("sag.final", 0) == 0)
    {
        return "m";
    }
    return "";
}

std::string sceneKeyUnit(const JsonPath& key)
{
    std::string last;
    for (const JsonPathStep& step : key.steps)
    {
        if (!step.isIndex)
        {
            last = step.key;
        }
    }
    if (endsWith(last, "_c"))
    {
        return "C";
    }
    if (endsWith(last, "_deg"))
    {
        return "deg";
    }
    if (last == "power")
    {
        return "W";
    }
    if (last == "time" || last == "duration" || last == "dt")
    {
        return "s";
    }
    if (last == "thickness" || last == "width" || last == "length" || last == "height" || last == "radius")
    {
        return "m";
    }
    return "";
}

const nlohmann::json* outputValue(const nlohmann::json& summary, const StudyOutput& output, nlohmann::json& scratch)
{
    if (output.path.rfind("event:", 0) == 0)
    {
        const std::string event = output.path.substr(6);
        const std::size_t colon = event.find(':');
        const std::string name = event.substr(0, colon);
        const std::string object = colon == std::string::npos ? "" : event.substr(colon + 1);
        if (!summary.contains("events") || !summary["events"].is_array())
        {
            return nullptr;
        }
        for (std::size_t i = 0; i < summary["events"].size(); ++i)
        {
            const nlohmann::json& e = summary["events"][i];
            if (!e.is_object() || !e.value("name", nlohmann::json("")).is_string() ||
                !e.value("object", nlohmann::json("")).is_string())
            {
                throw InputError("summary.json: events[" + std::to_string(i) +
                                 "] is not an event as masse run writes it ({\"name\", \"object\", \"sim_time\"})");
            }
            if (e.value("name", "") == name && (object.empty() || e.value("object", "") == object))
            {
                scratch = e.value("sim_time", nlohmann::json());
                return scratch.is_null() ? nullptr : &scratch;
            }
        }
        return nullptr;
    }
    return findAt(summary, parseJsonPath(output.path));
}

std::vector<KeyOverride> caseOverrides(const Study& study, std::size_t index)
{
    std::vector<KeyOverride> overrides = study.fixed;
    const std::vector<nlohmann::json>& values = study.cases.at(index);
    for (std::size_t p = 0; p < study.parameters.size(); ++p)
    {
        for (const StudyTarget& target : study.parameters[p].targets)
        {
            KeyOverride o;
            o.key = target.key;
            o.value = targetValue(values[p], target);
            o.text = study.parameters[p].where + ": " + target.key.text() + "=" + o.value.dump();
            overrides.push_back(std::move(o));
        }
    }
    return overrides;
}

nlohmann::json caseDocument(const Study& study, std::size_t index)
{
    nlohmann::json document = study.sceneDocument;
    applyKeyOverrides(document, caseOverrides(study, index), "");
    return document;
}

std::string describeCase(const Study& study, std::size_t index)
{
    std::string text;
    for (std::size_t p = 0; p < study.parameters.size(); ++p)
    {
        text += (p ? ", " : "") + study.parameters[p].name + "=" + valueText(study.cases.at(index)[p]);
    }
    return text;
}

Study loadStudy(const std::string& path)
{
    Study study;
    study.file = path;
    const nlohmann::json document = readJsonFile(path);
    const std::filesystem::path folder = std::filesystem::path(path).parent_path();
    try
    {
        const JsonObject top(document, "");
        study.name = top.string("name", std::filesystem::path(path).stem().string());
        if (std::any_of(study.name.begin(), study.name.end(),
                        [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7F; }))
        {
            // The name goes into the job's name, the plots' titles and the table: one line, printable.
            top.fail("name", "must be one line without control characters such as a newline or a tab");
        }
        top.string("description", "");
        const std::filesystem::path scene = top.string("scene");
        study.scenePath = (scene.is_absolute() ? scene : folder / scene).lexically_normal().string();
        try
        {
            study.sceneDocument = readSceneDocument(study.scenePath);
        }
        catch (const InputError& e)
        {
            top.fail("scene", e.what());
        }

        if (auto set = top.object("set"))
        {
            for (const std::string& key : set->keys())
            {
                KeyOverride o;
                try
                {
                    o.key = parseJsonPath(key);
                }
                catch (const InputError& e)
                {
                    top.fail("set", e.what());
                }
                o.value = *set->raw(key);
                o.text = "set." + key + "=" + o.value.dump();
                study.fixed.push_back(std::move(o));
            }
        }

        // The design decides what a parameter must give: value lists (grid, zip) or ranges to sample (hypercube).
        std::size_t samples = 0;
        std::uint64_t seed = 0;
        const nlohmann::json* design = top.raw("design");
        study.design = "grid";
        if (design && design->is_object())
        {
            const JsonObject d(*design, "design");
            const auto hypercube = d.object("latin_hypercube");
            if (!hypercube)
            {
                d.fail("latin_hypercube", "expected \"grid\", \"zip\" or {\"latin_hypercube\": {\"samples\": N, "
                                          "\"seed\": S}}");
            }
            samples = std::size_t(hypercube->integer("samples", 0, 1, int(maxCases)));
            if (!hypercube->has("samples"))
            {
                hypercube->fail("samples", "is required (how many cases)");
            }
            seed = std::uint64_t(hypercube->number("seed", 1.0, 0.0, 9.007199254740992e15));
            hypercube->finish();
            d.finish();
            study.design = "latin_hypercube";
        }
        else if (design)
        {
            study.design = top.choice("design", "grid", {"grid", "zip"});
        }

        std::vector<std::vector<nlohmann::json>> values;
        std::vector<StudyRange> ranges;
        const std::vector<JsonObject> vary = top.objects("vary");
        if (vary.empty())
        {
            top.fail("vary", "is required: a list of the keys to vary, such as [{\"key\": "
                             "\"heat.heaters[0].power\", \"values\": [6000, 8000]}]");
        }
        for (std::size_t p = 0; p < vary.size(); ++p)
        {
            const JsonObject& v = vary[p];
            StudyParameter parameter;
            parameter.where = "vary[" + std::to_string(p) + "]";
            if (v.has("key") == v.has("keys"))
            {
                v.fail("key", "give either key (one scene key) or keys (several set together)");
            }
            if (v.has("key"))
            {
                parameter.targets.push_back(readTarget(*v.raw("key"), v.pathOf("key")));
            }
            else
            {
                const nlohmann::json& keys = *v.raw("keys");
                if (!keys.is_array() || keys.empty())
                {
                    v.fail("keys", "expected a non-empty list of keys");
                }
                for (std::size_t k = 0; k < keys.size(); ++k)
                {
                    parameter.targets.push_back(readTarget(keys[k], v.pathOf("keys[" + std::to_string(k) + "]")));
                }
            }
            parameter.name = v.string("name", parameter.targets.front().key.text());
            parameter.unit = v.string("unit", sceneKeyUnit(parameter.targets.front().key));
            for (const StudyParameter& other : study.parameters)
            {
                if (other.name == parameter.name)
                {
                    v.fail("name", "'" + parameter.name + "' is already the name of another varied key");
                }
            }
            if (v.has("values") == v.has("range"))
            {
                v.fail("values", "give either values (a list) or range ({min, max, count or step})");
            }
            std::vector<nlohmann::json> list;
            StudyRange range;
            if (v.has("values"))
            {
                if (study.design == "latin_hypercube")
                {
                    v.fail("values", "a Latin hypercube samples ranges: give range {\"min\": ..., \"max\": ...}");
                }
                const nlohmann::json& given = *v.raw("values");
                if (!given.is_array() || given.empty())
                {
                    v.fail("values", "empty: expected a non-empty list of values");
                }
                list.assign(given.begin(), given.end());
            }
            else
            {
                list = readRangeValues(*v.object("range"), study.design == "latin_hypercube", range);
                if (study.design != "latin_hypercube" && list.empty())
                {
                    v.fail("range", "empty range: no values between min and max");
                }
            }
            for (const StudyTarget& target : parameter.targets)
            {
                if (target.scale != 1 || target.offset != 0)
                {
                    for (const nlohmann::json& value : list)
                    {
                        if (!value.is_number())
                        {
                            v.fail("keys", "scale and offset need numbers (got " + value.dump() + ")");
                        }
                    }
                }
            }
            v.finish();
            values.push_back(std::move(list));
            ranges.push_back(range);
            study.parameters.push_back(std::move(parameter));
        }

        if (study.design == "latin_hypercube")
        {
            study.cases = latinHypercube(ranges, samples, seed);
        }
        else if (study.design == "zip")
        {
            for (std::size_t p = 1; p < values.size(); ++p)
            {
                if (values[p].size() != values[0].size())
                {
                    top.fail("design", "zip pairs the i-th values, but vary[0] has " +
                                           std::to_string(values[0].size()) + " and vary[" + std::to_string(p) +
                                           "] has " + std::to_string(values[p].size()));
                }
            }
            study.cases = zipDesign(values);
        }
        else
        {
            double count = 1;
            for (const std::vector<nlohmann::json>& list : values)
            {
                count *= double(list.size());
            }
            if (count > double(maxCases))
            {
                top.fail("vary", "the grid has " + valueText(count) + " cases; at most " + std::to_string(maxCases));
            }
            study.cases = gridDesign(values);
        }

        const nlohmann::json* outputs = top.raw("outputs");
        if (!outputs || !outputs->is_array() || outputs->empty())
        {
            top.fail("outputs", "is required: a list of summary.json values to collect, such as "
                                "[\"final.thickness.min_ratio\", \"event:contact:mould\", \"realtime_factor\"]");
        }
        for (std::size_t i = 0; i < outputs->size(); ++i)
        {
            study.outputs.push_back(readOutput((*outputs)[i], "outputs[" + std::to_string(i) + "]"));
            for (std::size_t j = 0; j + 1 < study.outputs.size(); ++j)
            {
                if (study.outputs[j].name == study.outputs.back().name)
                {
                    top.fail("outputs[" + std::to_string(i) + "]",
                             "'" + study.outputs.back().name + "' is collected twice (give it another \"name\")");
                }
            }
        }
        top.finish();

        // Every case's scene is read now, so a value the scene refuses stops the study before anything runs.
        const std::string sceneFolder = std::filesystem::path(study.scenePath).parent_path().string();
        for (std::size_t i = 0; i < study.cases.size(); ++i)
        {
            try
            {
                const SceneSpec spec =
                    parseSceneWith(study.sceneDocument, caseOverrides(study, i), sceneFolder, study.scenePath, "");
                if (i == 0)
                {
                    Scene built(spec);
                    const nlohmann::json summary = summarize(built, 0);
                    const std::vector<std::string> added = summaryKeysAddedByTheRun(spec);
                    for (std::size_t o = 0; o < study.outputs.size(); ++o)
                    {
                        checkOutputPath(study.outputs[o], summary, added, "outputs[" + std::to_string(o) + "]");
                    }
                }
            }
            catch (const InputError& e)
            {
                const std::string what = e.what();
                if (what.rfind("outputs[", 0) == 0)
                {
                    throw;
                }
                throw InputError("case " + std::to_string(i) + " (" + describeCase(study, i) + "): " + what);
            }
        }
    }
    catch (const InputError& e)
    {
        throw InputError(path + ": " + e.what());
    }
    return study;
}
} // namespace masse::scene
