#pragma once
/// The subcommands of the `masse` program; each registers its options and its action on the parent app.

namespace CLI
{
class App;
}

namespace masse::app
{
void addLatticeCommand(CLI::App& app);
void addBenchCommand(CLI::App& app);
void addDemoCommand(CLI::App& app);
void addRunCommand(CLI::App& app);
void addPaperCommand(CLI::App& app);
void addCheckCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addViewCommand(CLI::App& app);
void addSweepCommand(CLI::App& app);
} // namespace masse::app
