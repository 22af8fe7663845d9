// The subcommands of `isotrace` (pbrt's cmd/): each file here adds one to
// the CLI11 app and says how to run it; main.cpp only wires them.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace isotrace {

/// Exit status of the isotrace command.
enum ExitCode : int {
    kExitSuccess = 0,
    /// `compare`: an image over its threshold (or with NaN pixels).
    kExitComparisonFailed = 1,
    /// Bad input or usage, or a file that cannot be read or written: the
    /// message names the file and the place in it.
    kExitBadInput = 2,
    /// A bug in isotrace (a broken invariant): the message says so.
    kExitInternalError = 3,
};

/// A subcommand added to the app and what runs when it is chosen.
struct Subcommand {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

Subcommand addRenderCommand(CLI::App& app);
Subcommand addPolygonizeCommand(CLI::App& app);
Subcommand addMergeCommand(CLI::App& app);
Subcommand addCompareCommand(CLI::App& app);
Subcommand addFitCommand(CLI::App& app);
Subcommand addPreviewCommand(CLI::App& app);
Subcommand addSampleCommand(CLI::App& app);
Subcommand addVoxelizeCommand(CLI::App& app);

/// Option checks that also refuse NaN and infinities (CLI11's
/// PositiveNumber lets NaN through).
CLI::Validator finitePositive();
CLI::Validator finiteNumber();
/// Digits only: a seed of "-1" would otherwise wrap around to 2^64 - 1.
CLI::Validator wholeNumber();

/// Runs a command's body and turns what it throws into an exit status and a
/// message on stderr: geometry::InputError and std::runtime_error (files,
/// memory, the environment) are bad input; anything else is an internal
/// error.
int runReportingErrors(const std::function<int()>& body);

/// Builds the whole command line and runs it.
int runIsotrace(int argc, const char* const* argv);

}  // namespace isotrace
