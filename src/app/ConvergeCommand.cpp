/// `masse converge SCENE --sizes 32,64,128 --out DIR`: runs a forming scene at several lattice sizes and writes how
/// far its thickness depends on the lattice, with a Richardson estimate and its error band (scene/study/Convergence.h).

#include "Commands.h"
#include "SceneOptions.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/NumericalError.h"
#include "scene/MemoryBudget.h"
#include "scene/Runner.h"
#include "scene/Scene.h"
#include "scene/output/AtomicFile.h"
#include "scene/output/OutputFolder.h"
#include "scene/output/Plot.h"
#include "scene/reports/ThicknessSectionReport.h"
#include "scene/reports/TopViewMap.h"
#include "scene/study/Convergence.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <unistd.h>

namespace masse::app
{
namespace
{
/// The bottom layer of a run at rest, with each mass's h / h0 at the end (RestLayerField).
scene::RestLayerField restLayerField(const scene::Scene& scene)
{
    const Lattice& lattice = scene.lattice();
    const SheetThickness& thickness = *scene.thickness();
    scene::RestLayerField field;
    field.rows = lattice.spec.countZ;
    field.columns = lattice.spec.countX;
    const std::size_t count = std::size_t(field.rows) * std::size_t(field.columns);
    field.x.resize(count);
    field.ratio.resize(count);
    field.z.resize(std::size_t(field.rows));
    for (Index i = lattice.layerStart[0]; i < lattice.layerStart[1]; ++i)
    {
        const LatticeCoord& c = lattice.coord[i];
        const std::size_t k = std::size_t(c.row) * std::size_t(field.columns) + std::size_t(c.column);
        field.x[k] = lattice.position[i].x();
        field.z[std::size_t(c.row)] = lattice.position[i].z();
        field.ratio[k] = thickness.thickness()[i] / thickness.initialThickness();
    }
    return field;
}

struct BandMap
{
    Real largest = 0;
    Real mean = 0;
};

/// The error band of each bottom-layer mass of the finest run: its h / h0 against the run before it read at the same
/// rest point, times the section's Richardson factor 1 / (r^p - 1) when the section was extrapolated (1 otherwise,
/// the difference itself), drawn on the finest run's formed sheet seen from above.
BandMap drawBandMap(const scene::Scene& finest, const scene::RestLayerField& coarser,
                    const std::vector<scene::ConvergenceRun>& runs, const scene::Convergence& convergence,
                    const std::string& pngPath)
{
    const scene::RichardsonEstimate& order = convergence.sectionOrder;
    const Real ratio = runs[runs.size() - 2].cellSize / runs.back().cellSize;
    const Real factor = order.extrapolated ? 1 / (std::pow(ratio, order.order) - 1) : Real(1);
    const Lattice& lattice = finest.lattice();
    const SheetThickness& thickness = *finest.thickness();
    std::vector<Real> band(lattice.massCount(), 0);
    BandMap figures;
    for (Index i = lattice.layerStart[0]; i < lattice.layerStart[1]; ++i)
    {
        const Vec3& rest = lattice.position[i];
        const Real fine = thickness.thickness()[i] / thickness.initialThickness();
        band[i] = factor * std::abs(fine - coarser.at(rest.x(), rest.z()));
        figures.largest = std::max(figures.largest, band[i]);
        figures.mean += band[i];
    }
    figures.mean /= Real(std::max<Index>(1, lattice.layerStart[1] - lattice.layerStart[0]));
    const std::string subtitle =
        runs[runs.size() - 2].size + " against " + runs.back().size +
        (order.extrapolated ? " (Richardson, order " + formatNumber("%.2f", order.order) + ")" : " (the difference)") +
        ": " + formatNumber("%.3f", figures.largest) + " h0 at most, " + formatNumber("%.3f", figures.mean) +
        " on average";
    scene::PlotBatch plots;
    scene::drawTopViewMap(plots, finest, band, pngPath, finest.spec().name + ": thickness error band, top view",
                          subtitle, "band (h/h0)", "rgb 21,22,23");
    plots.finish();
    return figures;
}
struct ConvergeOptions
{
    std::string scene;
    std::vector<std::string> sizes;
    std::string out;
    bool force = false;
    bool quiet = false;
    SceneOverrides overrides;
};

void runConverge(const ConvergeOptions& options)
{
    if (!options.overrides.size.empty())
    {
        throw InputError("--size: converge runs the sizes given by --sizes; leave --size out");
    }
    if (options.out.empty())
    {
        throw InputError("--out: converge writes its comparison and each size's run into a folder; give --out DIR");
    }
    // Every size is read, checked and costed before the output folder is touched: a bad size or one too large for
    // memory is refused with nothing written.
    const scene::SceneSpec base = loadSceneWithOverrides(options.scene, options.overrides);
    if (!base.material.enabled || !scene::sectionSettings(base))
    {
        throw InputError(options.scene + ": converge compares the thickness section: the scene needs a material and "
                                         "report.thickness_section");
    }
    const std::vector<std::string> sizes = scene::convergenceSizes(options.sizes, base.sheet.lattice);
    std::vector<scene::SceneSpec> specs;
    for (const std::string& size : sizes)
    {
        SceneOverrides overrides = options.overrides;
        overrides.size = size;
        scene::SceneSpec spec = loadSceneWithOverrides(options.scene, overrides);
        underFlag("--sizes", [&] { scene::checkMemory(spec); });
        specs.push_back(std::move(spec));
    }

    scene::OutputFolder folder(options.out, options.force);
    std::vector<scene::ConvergenceRun> runs;
    // The finest run is kept to draw the band map on its formed sheet, with the field of the run before it.
    std::unique_ptr<scene::Scene> finest;
    scene::RestLayerField coarser;
    scene::RestLayerField latest;
    for (std::size_t k = 0; k < specs.size(); ++k)
    {
        const scene::SceneSpec& spec = specs[k];
        const std::string runFolder = folder.staging() + "/" + sizes[k];
        std::filesystem::create_directories(runFolder);
        if (!options.quiet)
        {
            std::fprintf(stderr, "converge: %s (%zu of %zu)\n", sizes[k].c_str(), k + 1, specs.size());
        }
        const auto start = std::chrono::steady_clock::now();
        auto built = std::make_unique<scene::Scene>(spec);
        scene::Scene& scene = *built;
        scene::RunOptions run;
        run.outDir = runFolder;
        run.showProgress = !options.quiet;
        run.terminal = ::isatty(STDERR_FILENO) != 0;
        // A size that diverges ends the comparison (exit code 1, nothing written), saying which size it was.
        const scene::RunResult result = [&]
        {
            try
            {
                return scene::runScene(scene, run, std::cerr);
            }
            catch (const NumericalError& error)
            {
                throw NumericalError("converge: " + sizes[k] + ": " + error.what());
            }
        }();

        scene::ConvergenceRun entry;
        entry.size = sizes[k];
        entry.masses = scene.lattice().massCount();
        const LatticeSpec& lattice = spec.sheet.lattice;
        entry.cellSize = (lattice.maxCorner.x() - lattice.minCorner.x()) / Real(lattice.countX - 1);
        entry.thinnest = result.summary["final"]["thickness"]["min_ratio"].get<double>();
        entry.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        for (const scene::SectionPoint& point : scene::thicknessSection(scene))
        {
            entry.coordinate.push_back(point.restCoordinate);
            entry.ratio.push_back(point.ratio);
        }
        runs.push_back(std::move(entry));
        coarser = std::move(latest);
        latest = restLayerField(scene);
        finest = std::move(built);
    }

    const scene::Convergence convergence = scene::compareRuns(runs);
    const std::string csv = folder.staging() + "/convergence_section.csv";
    scene::writeFileAtomically(csv, scene::convergenceCsv(runs, convergence));
    scene::plotPng(scene::convergencePlotScript(csv, base.name, runs, convergence.sectionOrder.extrapolated),
                   folder.staging() + "/convergence_section.png");
    const BandMap band = drawBandMap(*finest, coarser, runs, convergence, folder.staging() + "/convergence_map.png");
    nlohmann::json summary = scene::convergenceSummary(base.name, runs, convergence);
    summary["map"] = {{"largest_band_ratio", band.largest}, {"mean_band_ratio", band.mean}};
    scene::writeFileAtomically(folder.staging() + "/convergence.json", summary.dump(2) + "\n");
    folder.commit();

    std::printf("%-12s %8s %10s %10s %12s %12s\n", "size", "masses", "thinnest", "wall s", "section mean",
                "section max");
    for (std::size_t k = 0; k < runs.size(); ++k)
    {
        std::printf("%-12s %8zu %10.4f %10.1f", runs[k].size.c_str(), runs[k].masses, runs[k].thinnest,
                    runs[k].wallSeconds);
        if (k > 0)
        {
            std::printf(" %12.4f %12.4f", convergence.meanDifference[k - 1], convergence.largestDifference[k - 1]);
        }
        std::printf("\n");
    }
    const scene::RichardsonEstimate& t = convergence.thinnest;
    if (t.extrapolated)
    {
        std::printf("thinnest wall: %.4f h0 +- %.4f (Richardson, order %.2f %s)\n", t.value, t.band, t.order,
                    t.orderMeasured ? "measured" : "assumed");
    }
    else if (t.orderMeasured)
    {
        std::printf("thinnest wall: %.4f h0 +- %.4f (the differences shrink too slowly, order %.2f measured, below "
                    "%.1f: not extrapolated; the band is the last difference)\n",
                    t.value, t.band, t.order, scene::minimumOrder);
    }
    else
    {
        std::printf("thinnest wall: %.4f h0 +- %.4f (the differences do not shrink: not extrapolated; the band is the "
                    "last difference)\n",
                    t.value, t.band);
    }
    std::printf("thickness map: band %.4f h0 at most, %.4f on average over the bottom layer (convergence_map.png)\n",
                band.largest, band.mean);
    std::printf("wrote %s/convergence.json, convergence_section.csv and .png, convergence_map.png, and each size's "
                "run\n",
                options.out.c_str());
}
} // namespace

void addConvergeCommand(CLI::App& app)
{
    auto options = std::make_shared<ConvergeOptions>();
    CLI::App* command = app.add_subcommand(
        "converge", "Run a forming scene at several lattice sizes; write how far its thickness depends on the lattice");
    command->add_option("scene", options->scene, "Scene file (JSON) with a material and report.thickness_section")
        ->required();
    command
        ->add_option("--sizes", options->sizes,
                     "Lattice sizes, coarsest first: N (the scene's layers and aspect) or NxLxM, e.g. 32,64,128")
        ->delimiter(',')
        ->required();
    command->add_option("--out", options->out, "Output folder (written when every size has run, never half)");
    command->add_flag("--force", options->force, "Replace an --out folder that already holds files");
    command->add_flag("--quiet", options->quiet, "No progress display");
    addThreadsOption(*command, options->overrides.engine);
    addSceneOverrides(*command, options->overrides);
    command->callback([options] { runConverge(*options); });
}
} // namespace masse::app
