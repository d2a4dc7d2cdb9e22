#include "scene/study/Convergence.h"

#include "core/InputError.h"
#include "scene/MemoryBudget.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace masse::scene
{
namespace
{
bool allDigits(const std::string& text)
{
    return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

/// f at x from the points (xs, fs), xs increasing: linear between them, the end value beyond them.
Real interpolate(const std::vector<Real>& xs, const std::vector<Real>& fs, Real x)
{
    if (x <= xs.front())
    {
        return fs.front();
    }
    if (x >= xs.back())
    {
        return fs.back();
    }
    const std::size_t k = std::size_t(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin());
    const Real t = (x - xs[k - 1]) / (xs[k] - xs[k - 1]);
    return fs[k - 1] + t * (fs[k] - fs[k - 1]);
}

/// d1 / d2 for order p (see observedOrder).
Real differenceRatio(Real p, Real ratio1, Real ratio2)
{
    return std::pow(ratio2, p) * (std::pow(ratio1, p) - 1) / (std::pow(ratio2, p) - 1);
}
} // namespace

std::vector<std::string> convergenceSizes(const std::vector<std::string>& given, const LatticeSpec& scene)
{
    if (given.size() < 2)
    {
        throw InputError("--sizes: give at least two lattice sizes, coarsest first, e.g. --sizes 32,64,128 (got " +
                         std::to_string(given.size()) + ")");
    }
    std::vector<std::string> sizes;
    std::size_t previousMasses = 0;
    std::string previous;
    for (const std::string& text : given)
    {
        LatticeSpec spec = scene;
        if (allDigits(text) && text.size() <= 6)
        {
            const int columns = std::stoi(text);
            const int rows = std::max(2, int(std::lround(Real(columns) * Real(scene.countZ) / Real(scene.countX))));
            spec.countX = columns;
            spec.countZ = rows;
        }
        else
        {
            try
            {
                parseSize(text, spec);
            }
            catch (const InputError& error)
            {
                throw InputError("--sizes: '" + text +
                                 "' is not a size (N, or NxLxM such as 64x2x64): " + error.what());
            }
        }
        try
        {
            validate(spec);
        }
        catch (const InputError& error)
        {
            throw InputError("--sizes: " + text + ": " + error.what());
        }
        const std::string size =
            std::to_string(spec.countX) + "x" + std::to_string(spec.layers) + "x" + std::to_string(spec.countZ);
        const std::size_t masses = massCountOf(spec);
        if (!sizes.empty() && masses <= previousMasses)
        {
            throw InputError("--sizes: give the sizes coarsest first: " + size + " (" + std::to_string(masses) +
                             " masses) after " + previous + " (" + std::to_string(previousMasses) + " masses)");
        }
        sizes.push_back(size);
        previous = size;
        previousMasses = masses;
    }
    return sizes;
}

Real observedOrder(Real d1, Real d2, Real ratio1, Real ratio2)
{
    if (!(d2 != 0) || !(d1 / d2 > 0) || !(ratio1 > 1) || !(ratio2 > 1))
    {
        return 0;
    }
    const Real target = d1 / d2;
    Real low = 1e-6;
    Real high = 8;
    if (!(target > differenceRatio(low, ratio1, ratio2)) || !(target < differenceRatio(high, ratio1, ratio2)))
    {
        return 0;
    }
    for (int i = 0; i < 200 && high - low > 1e-12; ++i)
    {
        const Real middle = (low + high) / 2;
        (differenceRatio(middle, ratio1, ratio2) < target ? low : high) = middle;
    }
    return (low + high) / 2;
}

RichardsonEstimate richardson(const std::vector<Real>& values, const std::vector<Real>& cellSizes)
{
    RichardsonEstimate estimate;
    const std::size_t n = values.size();
    const Real fine = values[n - 1];
    const Real coarser = values[n - 2];
    const Real lastRatio = cellSizes[n - 2] / cellSizes[n - 1];
    estimate.value = fine;
    estimate.band = std::abs(fine - coarser);
    if (fine == coarser)
    {
        estimate.extrapolated = true; // nothing to extrapolate: the band is 0
        estimate.band = 0;
        return estimate;
    }
    if (n >= 3)
    {
        estimate.order =
            observedOrder(values[n - 3] - coarser, coarser - fine, cellSizes[n - 3] / cellSizes[n - 2], lastRatio);
        estimate.orderMeasured = estimate.order > 0;
        if (estimate.order < minimumOrder)
        {
            return estimate;
        }
    }
    else
    {
        estimate.order = 1;
    }
    estimate.value = fine + (fine - coarser) / (std::pow(lastRatio, estimate.order) - 1);
    estimate.band = std::abs(estimate.value - fine);
    estimate.extrapolated = true;
    return estimate;
}

Convergence compareRuns(const std::vector<ConvergenceRun>& runs)
{
    Convergence c;
    const ConvergenceRun& finest = runs.back();
    c.coordinate = finest.coordinate;
    for (const ConvergenceRun& run : runs)
    {
        std::vector<Real> at;
        at.reserve(c.coordinate.size());
        for (Real x : c.coordinate)
        {
            at.push_back(interpolate(run.coordinate, run.ratio, x));
        }
        c.ratio.push_back(std::move(at));
    }
    for (std::size_t k = 0; k + 1 < runs.size(); ++k)
    {
        Real sum = 0;
        Real largest = 0;
        for (std::size_t i = 0; i < c.coordinate.size(); ++i)
        {
            const Real d = std::abs(c.ratio[k + 1][i] - c.ratio[k][i]);
            sum += d;
            largest = std::max(largest, d);
        }
        c.meanDifference.push_back(sum / Real(c.coordinate.size()));
        c.largestDifference.push_back(largest);
        // Relative to the finer run's thinnest wall; a wall drawn to nothing there gives the change itself.
        const Real change = std::abs(runs[k + 1].thinnest - runs[k].thinnest);
        c.thinnestChange.push_back(runs[k + 1].thinnest > 0 ? change / runs[k + 1].thinnest : change);
    }

    std::vector<Real> cellSizes;
    std::vector<Real> thinnest;
    for (const ConvergenceRun& run : runs)
    {
        cellSizes.push_back(run.cellSize);
        thinnest.push_back(run.thinnest);
    }
    c.thinnest = richardson(thinnest, cellSizes);

    // One order for the whole section, from how its mean difference shrinks: a point's own differences are too
    // noisy to measure one (a wall moving by a cell changes sign from one size to the next).
    const std::size_t n = runs.size();
    const Real lastRatio = cellSizes[n - 2] / cellSizes[n - 1];
    Real order = 1;
    if (n >= 3)
    {
        order = observedOrder(c.meanDifference[n - 3], c.meanDifference[n - 2], cellSizes[n - 3] / cellSizes[n - 2],
                              lastRatio);
        c.sectionOrder.orderMeasured = order > 0;
    }
    c.sectionOrder.order = order;
    c.sectionOrder.extrapolated = order >= minimumOrder;
    for (std::size_t i = 0; i < c.coordinate.size(); ++i)
    {
        const Real fine = c.ratio[n - 1][i];
        const Real coarser = c.ratio[n - 2][i];
        if (c.sectionOrder.extrapolated)
        {
            const Real value = fine + (fine - coarser) / (std::pow(lastRatio, order) - 1);
            c.estimate.push_back(value);
            c.band.push_back(std::abs(value - fine));
        }
        else
        {
            c.estimate.push_back(fine);
            c.band.push_back(std::abs(fine - coarser));
        }
    }
    return c;
}

Real RestLayerField::at(Real px, Real pz) const
{
    const auto alongRow = [&](int row)
    {
        const Real* xs = x.data() + std::size_t(row) * std::size_t(columns);
        const Real* values = ratio.data() + std::size_t(row) * std::size_t(columns);
        if (columns == 1 || px <= xs[0])
        {
            return values[0];
        }
        if (px >= xs[columns - 1])
        {
            return values[columns - 1];
        }
        const int right = int(std::upper_bound(xs, xs + columns, px) - xs);
        const Real t = (px - xs[right - 1]) / (xs[right] - xs[right - 1]);
        return (1 - t) * values[right - 1] + t * values[right];
    };
    if (rows == 1 || pz <= z.front())
    {
        return alongRow(0);
    }
    if (pz >= z.back())
    {
        return alongRow(rows - 1);
    }
    const int above = int(std::upper_bound(z.begin(), z.end(), pz) - z.begin());
    const Real t = (pz - z[std::size_t(above - 1)]) / (z[std::size_t(above)] - z[std::size_t(above - 1)]);
    return (1 - t) * alongRow(above - 1) + t * alongRow(above);
}

nlohmann::json convergenceSummary(const std::string& scene, const std::vector<ConvergenceRun>& runs,
                                  const Convergence& c)
{
    nlohmann::json document;
    document["scene"] = scene;
    for (const ConvergenceRun& run : runs)
    {
        document["sizes"].push_back({{"size", run.size},
                                     {"masses", run.masses},
                                     {"cell_size_m", run.cellSize},
                                     {"thinnest_ratio", run.thinnest},
                                     {"wall_seconds", run.wallSeconds},
                                     {"folder", run.size}});
    }
    for (std::size_t k = 0; k + 1 < runs.size(); ++k)
    {
        document["differences"].push_back({{"from", runs[k].size},
                                           {"to", runs[k + 1].size},
                                           {"section_mean", c.meanDifference[k]},
                                           {"section_largest", c.largestDifference[k]},
                                           {"thinnest_change", c.thinnestChange[k]}});
    }
    auto estimateJson = [](const RichardsonEstimate& e) {
        return nlohmann::json{
            {"extrapolated", e.extrapolated}, {"order", e.order}, {"order_measured", e.orderMeasured}};
    };
    nlohmann::json thinnest = estimateJson(c.thinnest);
    thinnest["estimate_ratio"] = c.thinnest.value;
    thinnest["band_ratio"] = c.thinnest.band;
    document["thinnest"] = thinnest;
    nlohmann::json section = estimateJson(c.sectionOrder);
    section["largest_band_ratio"] = c.band.empty() ? 0.0 : *std::max_element(c.band.begin(), c.band.end());
    Real sum = 0;
    for (Real b : c.band)
    {
        sum += b;
    }
    section["mean_band_ratio"] = c.band.empty() ? 0.0 : sum / Real(c.band.size());
    document["section"] = section;
    return document;
}

std::string convergenceCsv(const std::vector<ConvergenceRun>& runs, const Convergence& c)
{
    std::ostringstream out;
    out << "coordinate_m";
    for (const ConvergenceRun& run : runs)
    {
        out << ",ratio_" << run.size;
    }
    out << ",estimate,band\n";
    char buffer[32];
    for (std::size_t i = 0; i < c.coordinate.size(); ++i)
    {
        std::snprintf(buffer, sizeof buffer, "%.6f", c.coordinate[i]);
        out << buffer;
        for (std::size_t k = 0; k < runs.size(); ++k)
        {
            std::snprintf(buffer, sizeof buffer, ",%.6f", c.ratio[k][i]);
            out << buffer;
        }
        std::snprintf(buffer, sizeof buffer, ",%.6f", c.estimate[i]);
        out << buffer;
        std::snprintf(buffer, sizeof buffer, ",%.6f\n", c.band[i]);
        out << buffer;
    }
    return out.str();
}

std::string convergencePlotScript(const std::string& csvPath, const std::string& title,
                                  const std::vector<ConvergenceRun>& runs, bool extrapolated)
{
    const std::size_t estimateColumn = runs.size() + 2;
    const std::string estimate = std::to_string(estimateColumn);
    const std::string band = std::to_string(estimateColumn + 1);
    std::string script = "set datafile separator ','\n"
                         "set title '" +
                         title +
                         ": thickness along the section, by lattice'\n"
                         "set xlabel 'position along the section at rest (m)'\n"
                         "set ylabel 'thickness h / h0'\n"
                         "set yrange [0:*]\n"
                         "set grid\n"
                         "set key bottom right\n"
                         "plot '" +
                         csvPath + "' every ::1 using 1:($" + estimate + "-$" + band + "):($" + estimate + "+$" + band +
                         ") with filledcurves fs transparent solid 0.25 lc rgb '#888888' title 'estimate +- band'";
    for (std::size_t k = 0; k < runs.size(); ++k)
    {
        script += ", '' every ::1 using 1:" + std::to_string(k + 2) + " with lines lw 1.5 title '" + runs[k].size + "'";
    }
    script += ", '' every ::1 using 1:" + estimate + " with lines lw 2 dt 2 lc rgb 'black' title '" +
              (extrapolated ? "Richardson estimate" : "not converging: finest run") + "'\n";
    return script;
}
} // namespace masse::scene
