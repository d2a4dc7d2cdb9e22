#pragma once
/// Running statistics of the implicit solver over a run: what summary.json and `masse bench` report, and what tells a
/// user that steps stopped at the iteration cap (their result is less accurate than the tolerance asks).

#include "core/integrate/Integrator.h"

#include <algorithm>
#include <cstdint>

namespace masse
{
struct SolverTally
{
    std::uint64_t solves = 0;           ///< implicit steps (substeps) solved
    std::uint64_t iterations = 0;       ///< summed over them
    int largestIterations = 0;          ///< in one step
    std::uint64_t capHits = 0;          ///< steps that stopped at the iteration cap
    Real finalResidual = 0;             ///< residual of the last solve, over its tolerance's scale (IntegratorStats)
    Real largestResidual = 0;           ///< over all solves
    std::uint64_t refactorisations = 0; ///< preconditioner rebuilds (the Cholesky factor's or the multigrid's)

    void add(const IntegratorStats& stats)
    {
        ++solves;
        iterations += std::uint64_t(stats.solverIterations);
        largestIterations = std::max(largestIterations, stats.solverIterations);
        capHits += stats.hitIterationCap ? 1 : 0;
        finalResidual = stats.solverResidual;
        largestResidual = std::max(largestResidual, stats.solverResidual);
        refactorisations += std::uint64_t(stats.refactorisations);
    }
    Real meanIterations() const { return solves > 0 ? Real(iterations) / Real(solves) : Real(0); }
};
} // namespace masse
