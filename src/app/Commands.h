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
void addConvergeCommand(CLI::App& app);

/// The whole command line: parses argv, runs the subcommand and returns the exit code (0, 1 or 2). `main` calls it,
/// and so does a sweep's worker, forked from the sweep, so a case runs exactly as `masse run` would without loading
/// the program again.
int masseMain(int argc, char** argv);
} // namespace masse::app
