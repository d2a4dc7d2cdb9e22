#pragma once
/// How far a forming result depends on the lattice: a scene run at several lattice sizes, its thickness section and
/// thinnest wall compared size by size, and a Richardson estimate of the values a lattice without end would give,
/// with the distance to the finest run as the error band (`masse converge`, docs/heat-and-forming.md).
///
/// Richardson: a value f computed on cells of size h behaves as f(h) = f* + C h^p for small h. Three sizes measure
/// the order p from how the differences shrink, and f* = f_fine + (f_fine - f_coarser) / ((h_coarser / h_fine)^p - 1).
/// Two sizes cannot measure p: it is taken as 1, the slowest convergence of a consistent lattice, whose correction
/// is the largest of the usual orders. Differences that do not shrink from one size to the next are not extrapolated:
/// the estimate is the finest run's value and the band the last difference. Nor are differences that shrink more
/// slowly than order minimumOrder: the runs are not yet where f behaves as C h^p, and the correction would reach far
/// past them (a thinnest wall moving by 0.0064 then 0.0062 h0 as the cells halve measures order 0.03, whose f* is
/// -0.09 h0).

#include "core/Types.h"
#include "core/lattice/Lattice.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace masse::scene
{
/// The sizes `masse converge --sizes` asks for: each "N" (N masses along x, the scene's layers and its aspect:
/// N x L x round(N * Nz / Nx)) or "NxLxM". At least two, each with more masses than the one before. Throws
/// InputError naming --sizes.
std::vector<std::string> convergenceSizes(const std::vector<std::string>& given, const LatticeSpec& scene);

/// The smallest measured order extrapolated: differences that shrink by less than a factor of 1.41 as the cells halve.
/// Below it, f* would lie more than 2.4 last differences (1 / (2^p - 1)) beyond the finest run.
constexpr Real minimumOrder = 0.5;

/// The order p and the estimate f* from values f_k on cells of sizes h_k, coarsest first (see above).
struct RichardsonEstimate
{
    Real value = 0; ///< f*, or the finest value when not extrapolated
    Real band = 0;  ///< |f* - f_fine|, or the last difference when not extrapolated
    Real order = 0; ///< p: measured (three or more sizes), 1 assumed (two); 0 when the differences did not shrink
    bool extrapolated = false; ///< false when the differences did not shrink, or shrank slower than minimumOrder
    bool orderMeasured = false;
};
RichardsonEstimate richardson(const std::vector<Real>& values, const std::vector<Real>& cellSizes);
/// The order p measured from the last three differences' sizes d1 (coarser pair) and d2 (finer pair), on cells whose
/// sizes fall by `ratio1` then `ratio2`: solves d1 / d2 = (r1^p - 1) r2^p / (r2^p - 1) by bisection on p in (0, 8).
/// Returns 0 when the differences do not shrink or no p in that range fits.
Real observedOrder(Real d1, Real d2, Real ratio1, Real ratio2);

/// One lattice size's run: its section (h / h0 against the rest coordinate along the section's axis) and thinnest
/// wall (h / h0, over every mass of every layer).
struct ConvergenceRun
{
    std::string size;
    std::size_t masses = 0;
    Real cellSize = 0; ///< m, along x at rest
    Real thinnest = 0;
    Real wallSeconds = 0;
    std::vector<Real> coordinate; ///< m, increasing
    std::vector<Real> ratio;
};

/// The comparison of the runs (coarsest first): the section of each run at the finest run's coordinates (linear
/// between a coarser run's points), consecutive runs' mean and largest differences, the thinnest walls, and the
/// Richardson estimates of the section (one order for the whole section, measured from its mean differences) and of
/// the thinnest wall.
struct Convergence
{
    std::vector<Real> coordinate;         ///< the finest run's
    std::vector<std::vector<Real>> ratio; ///< per run, at `coordinate`
    std::vector<Real> meanDifference;     ///< per consecutive pair, of h / h0
    std::vector<Real> largestDifference;  ///< per consecutive pair
    std::vector<Real> thinnestChange;     ///< per consecutive pair: |t_fine - t_coarse| / t_fine
    std::vector<Real> estimate;           ///< per point of `coordinate`
    std::vector<Real> band;               ///< per point
    RichardsonEstimate sectionOrder;      ///< the section's order (its value and band unused)
    RichardsonEstimate thinnest;
};
Convergence compareRuns(const std::vector<ConvergenceRun>& runs);

/// A run's bottom layer at rest: h / h0 of each of its masses, row by row (a row runs along x at one z) with their rest
/// positions, read anywhere on the sheet to compare a finer run's masses with it (the band map of `masse converge`).
/// Rows may be shifted against each other along x (a triangular lattice's are): a point is read along x within the
/// rows on either side of it, then between those rows along z.
struct RestLayerField
{
    int rows = 0;
    int columns = 0;
    std::vector<Real> x;     ///< m, rest, rows x columns, increasing along each row
    std::vector<Real> z;     ///< m, rest, one per row, increasing
    std::vector<Real> ratio; ///< h / h0, rows x columns
    /// h / h0 at the rest point (x, z), linear between the masses around it; a point beyond the edge takes the edge's.
    Real at(Real px, Real pz) const;
};

/// convergence.json's document, convergence_section.csv and its gnuplot script.
nlohmann::json convergenceSummary(const std::string& scene, const std::vector<ConvergenceRun>& runs,
                                  const Convergence& convergence);
std::string convergenceCsv(const std::vector<ConvergenceRun>& runs, const Convergence& convergence);
std::string convergencePlotScript(const std::string& csvPath, const std::string& title,
                                  const std::vector<ConvergenceRun>& runs, bool extrapolated);
} // namespace masse::scene
