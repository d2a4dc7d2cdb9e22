/// `masse lattice`: the counts of a sheet lattice, for checking a structure and size before running it.

#include "Commands.h"
#include "SceneOptions.h"

#include "core/lattice/Lattice.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>
#include <memory>

namespace masse::app
{
namespace
{
struct LatticeOptions
{
    std::string structure = "trimm";
    std::string size = "8x2x8";
    bool json = false;
};

void runLattice(const LatticeOptions& options)
{
    LatticeSpec spec;
    underFlag("--structure", [&] { spec.structure = parseStructure(options.structure); });
    underFlag("--size",
              [&]
              {
                  parseSize(options.size, spec);
                  validate(spec);
              });
    const Lattice lattice = buildLattice(spec);

    std::size_t planar = 0;
    for (SpringClass cls : lattice.springs.classes())
    {
        planar += cls == SpringClass::Planar ? 1 : 0;
    }
    const std::size_t interLayer = lattice.springCount() - planar;

    if (options.json)
    {
        nlohmann::json out = {
            {"structure", structureName(spec.structure)},
            {"size", options.size},
            {"layers", spec.layers},
            {"masses", lattice.massCount()},
            {"springs", lattice.springCount()},
            {"planar_springs", planar},
            {"inter_layer_springs", interLayer},
            {"spacing_x", lattice.spacingX},
            {"spacing_z", lattice.spacingZ},
        };
        std::cout << out.dump() << "\n";
        return;
    }
    std::printf("structure     %s\n", std::string(structureName(spec.structure)).c_str());
    std::printf("size          %dx%dx%d (x, layers, z)\n", spec.countX, spec.layers, spec.countZ);
    std::printf("layers        %d\n", spec.layers);
    std::printf("masses        %zu\n", lattice.massCount());
    std::printf("springs       %zu (planar %zu, inter-layer %zu)\n", lattice.springCount(), planar, interLayer);
    std::printf("spacing       x %.6g m, z %.6g m\n", lattice.spacingX, lattice.spacingZ);
}
} // namespace

void addLatticeCommand(CLI::App& app)
{
    auto options = std::make_shared<LatticeOptions>();
    CLI::App* command = app.add_subcommand("lattice", "Print the mass and spring counts of a sheet lattice");
    command->add_option("--structure", options->structure, structureNameList())->capture_default_str();
    command->add_option("--size", options->size, "NxLxN: masses along x, layers, masses along z")
        ->capture_default_str();
    command->add_flag("--json", options->json, "Print one JSON object");
    command->callback([options] { runLattice(*options); });
}
} // namespace masse::app
