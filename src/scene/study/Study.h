#pragma once
/// A parameter study: a base scene, the keys to vary and how (lists, ranges, grid, zip or Latin hypercube), keys set
/// for every case, and the summary.json values to collect. The study format: data/studies/README.md.

#include "scene/SceneOverrides.h"
#include "scene/json/JsonPath.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace masse::scene
{
/// A scene key a parameter sets: value * scale + offset (scale and offset only for numbers).
struct StudyTarget
{
    JsonPath key;
    double scale = 1;
    double offset = 0;
};

struct StudyParameter
{
    std::string name;
    std::string unit;
    std::vector<StudyTarget> targets;
    std::string where; ///< "vary[1]", for messages
};

/// A value to collect from each case's summary.json: a path (`final.thickness.min_ratio`) or an event's simulated
/// time (`event:contact:mould`, the first contact event with the obstacle "mould").
struct StudyOutput
{
    std::string name;
    std::string path;
    std::string unit;
};

struct Study
{
    std::string file; ///< the study file as given
    std::string name;
    std::string scenePath; ///< the base scene, as a path from the working folder
    nlohmann::json sceneDocument;
    std::vector<KeyOverride> fixed; ///< "set": keys every case sets
    std::vector<StudyParameter> parameters;
    std::vector<StudyOutput> outputs;
    std::vector<std::vector<nlohmann::json>> cases; ///< one value per parameter
    std::string design;
};

/// Reads a study, makes its cases and checks every case's scene as `masse run` would read it, and every output
/// against the scene's summary. Throws InputError "<study>: <key>: <what is wrong>" naming the study key, the case
/// and the scene key for a value the scene refuses; nothing has been run or written then.
Study loadStudy(const std::string& path);

/// The keys case `index` sets (the fixed ones, then the varied ones).
std::vector<KeyOverride> caseOverrides(const Study& study, std::size_t index);

/// The base scene with the case's keys set.
nlohmann::json caseDocument(const Study& study, std::size_t index);

/// "heat.heaters[0].power=8000, heating_time=30": a case's values, for messages and tables.
std::string describeCase(const Study& study, std::size_t index);

/// The value of an output in a summary (nullptr if absent: an event that did not happen, a key the scene lacks).
const nlohmann::json* outputValue(const nlohmann::json& summary, const StudyOutput& output, nlohmann::json& scratch);

/// The unit of a summary value by its path ("s", "m", "J", "C", "1" for ratios; "" if unknown).
std::string summaryUnit(const std::string& path);

/// The unit of a scene key by its last part (power: W, time: s, *_c: C...; "" if unknown).
std::string sceneKeyUnit(const JsonPath& key);

/// A value as text: numbers in their shortest exact form, strings bare, anything else as JSON.
std::string valueText(const nlohmann::json& value);
} // namespace masse::scene
