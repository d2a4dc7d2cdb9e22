#pragma once
/// `masse sweep --collect DIR`: one row per case (its varied values and collected outputs) in results.csv, a plot of
/// every output against every numeric varied key, and a table for the terminal. Works the same on a study run
/// locally or by Slurm array tasks, finished or not.

#include "scene/study/StudyFolder.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace masse::scene
{
struct CollectedCase
{
    std::size_t index = 0;
    std::string status; ///< "done", "failed" or "not run"
    int exitCode = -1;
    std::string message; ///< why it failed
    std::vector<nlohmann::json> values;
    std::vector<nlohmann::json> outputs; ///< null where the case has no such value
};

struct StudyResults
{
    StudyRecord record;
    std::vector<CollectedCase> cases;
    std::size_t done = 0;
    std::size_t failed = 0;
    std::size_t notRun = 0;
};

/// Reads every case's status and summary.json.
StudyResults collectResults(const std::string& dir);

/// case,status,exit_code,<varied key [unit]>...,<output [unit]>...,message
std::string resultsCsv(const StudyResults& results);

/// The same as an aligned table.
std::string resultsTable(const StudyResults& results);

/// DIR/plots/<output>-vs-<key>.png for every output and every varied key with numeric values; with two varied keys,
/// one line per value of the other key. Returns the files written.
std::vector<std::string> plotResults(const StudyResults& results, const std::string& dir);
} // namespace masse::scene
