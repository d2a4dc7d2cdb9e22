/// `masse`: the MaSSE command line. Exit codes: 0 success, 1 a run that failed (diverged, could not write),
/// 2 bad input (a flag, a scene, a mesh), with a message naming what is wrong.

#include "Commands.h"

#include "core/InputError.h"
#include "core/NearestName.h"
#include "core/NumericalError.h"
#include "core/Simulator.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

int masse::app::masseMain(int argc, char** argv)
{
    CLI::App app("MaSSE: Mass-Spring Simulation Engine for heat-sensitive sheets", "masse");
    app.require_subcommand(1);
    app.set_help_all_flag("--help-all", "Print help for every command");
    masse::app::addLatticeCommand(app);
    masse::app::addBenchCommand(app);
    masse::app::addDemoCommand(app);
    masse::app::addRunCommand(app);
    masse::app::addPaperCommand(app);
    masse::app::addCheckCommand(app);
    masse::app::addCompareCommand(app);
    masse::app::addViewCommand(app);
    masse::app::addSweepCommand(app);
    masse::app::addConvergeCommand(app);

    if (argc > 1 && argv[1][0] != '-')
    {
        // CLI11 says only "A subcommand is required" for a mistyped one.
        std::vector<std::string> names;
        const CLI::App& commands = app;
        for (const CLI::App* command : commands.get_subcommands([](const CLI::App*) { return true; }))
        {
            names.push_back(command->get_name());
        }
        if (std::find(names.begin(), names.end(), argv[1]) == names.end())
        {
            std::cerr << "masse: unknown command '" << argv[1] << "'" << masse::didYouMean(argv[1], names)
                      << "\n(run 'masse --help' for the commands and their options)\n";
            return 2;
        }
    }
    try
    {
        app.parse(argc, argv);
    }
    catch (const CLI::CallForHelp& e)
    {
        return app.exit(e);
    }
    catch (const CLI::CallForAllHelp& e)
    {
        return app.exit(e);
    }
    catch (const CLI::ParseError& e)
    {
        std::cerr << "masse: " << e.what() << "\n(run 'masse --help' for the commands and their options)\n";
        return 2;
    }
    catch (const masse::InputError& e)
    {
        std::cerr << "masse: " << e.what() << "\n";
        return 2;
    }
    catch (const masse::NumericalError& e)
    {
        std::cerr << "masse: " << e.what() << "\n";
        return 1;
    }
    catch (const std::exception& e)
    {
        std::cerr << "masse: error: " << e.what() << "\n";
        return 1;
    }
    return 0;
}

int main(int argc, char** argv)
{
    return masse::app::masseMain(argc, argv);
}
