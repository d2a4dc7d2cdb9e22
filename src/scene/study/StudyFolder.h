#pragma once
/// A study's output folder, shared by local runs, Slurm array tasks and --collect:
///   DIR/study.json     the study as run: parameters, outputs, every case's values (what --collect reads)
///   DIR/cases.csv      the manifest: case number, folder, varied values
///   DIR/cases/NNNN/    scene.json (the case's whole scene), then run.log, status.txt and the run's outputs; its
///                      manifest (.masse-manifest.json) lists all of them as MaSSE's
/// status.txt ("exit_code=N", "wall_seconds=S") is written last, by whoever ran the case, so a case is finished
/// exactly when it has one.

#include "scene/study/Study.h"

#include <string>
#include <vector>

namespace masse::scene
{
/// What --collect needs to know of a study, read back from DIR/study.json.
struct StudyRecord
{
    std::string name;
    std::string scene;
    std::vector<StudyParameter> parameters; ///< names and units (targets hold only the keys' paths)
    std::vector<StudyOutput> outputs;
    std::vector<std::vector<nlohmann::json>> cases;
};

struct CaseStatus
{
    bool finished = false;
    int exitCode = -1;
    double wallSeconds = 0;
};

/// DIR/cases/0003.
std::string caseFolder(const std::string& dir, std::size_t index);

/// Writes study.json, cases.csv and every case's scene.json. A folder that already holds this same study (same
/// cases, same scenes) is kept as it is, so the study resumes; one that holds another study or other files is
/// refused (InputError) with nothing written.
void prepareStudyFolder(const Study& study, const std::string& dir);

/// Reads DIR/study.json; throws InputError if DIR is not a study folder.
StudyRecord readStudyRecord(const std::string& dir);

/// Whether `path` is a regular file (following links): a pipe, a device or a folder in a case's file is not read.
bool isRegularFile(const std::string& path);

CaseStatus readCaseStatus(const std::string& caseDir);
void writeCaseStatus(const std::string& caseDir, int exitCode, double wallSeconds);

/// The cases without a status (and with `retryFailed`, those that failed too), in order.
std::vector<std::size_t> casesToRun(const std::string& dir, std::size_t caseCount, bool retryFailed);

/// Removes what an earlier, interrupted or failed run of the case left: what the case folder's manifest lists, but
/// scene.json (a file the manifest does not list stays, and the case's run then refuses the folder, naming it).
void clearCaseOutputs(const std::string& caseDir);

/// The last line of the case's run.log that says something (the error of a failed run), without "masse: ".
std::string lastLogLine(const std::string& caseDir);

/// A CSV field, quoted when it holds a comma, a quote or a line break.
std::string csvField(const std::string& text);

/// A column's heading: the name, and its unit in brackets when it has one ("power [W]").
std::string columnHeader(const std::string& name, const std::string& unit);
} // namespace masse::scene
