#pragma once
/// The paper's experiment (section 9, Figure 18): the drop scene run for the five sheet sizes of Table 2, timing
/// each of the four stages in simulated and wall-clock time.

#include "scene/SceneSpec.h"

#include <functional>
#include <string>
#include <vector>

namespace masse::scene
{
/// The four stages, in the order the paper times them.
inline const std::vector<std::string> paperStages = {"first polyhedron", "second polyhedron", "floor", "rest"};

struct PaperRow
{
    int size = 0; ///< N of the N x 2 x N sheet
    std::size_t masses = 0;
    std::size_t springs = 0;
    std::vector<Real> simTime;  ///< s, per stage; negative if the stage never came
    std::vector<Real> wallTime; ///< s, per stage
    bool inOrder = false;       ///< the four stages came, in the paper's order
};

/// The Table 2 sizes: 3, 6, 8, 9, 12.
inline const std::vector<int> paperSizes = {3, 6, 8, 9, 12};

/// Runs `base` (the drop scene: its first two obstacles are the polyhedra) once per size. `onRow` is called after
/// each size, for progress.
std::vector<PaperRow> runPaperExperiment(const SceneSpec& base, const std::vector<int>& sizes,
                                         const std::function<void(const PaperRow&)>& onRow = {});

/// The printed table: sheet, masses, springs, and simulated / wall seconds at each stage.
std::string paperTable(const std::vector<PaperRow>& rows);
/// figure18.csv: one row per size.
std::string paperCsv(const std::vector<PaperRow>& rows);
} // namespace masse::scene
