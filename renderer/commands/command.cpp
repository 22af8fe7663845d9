#include "renderer/commands/command.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <stdexcept>
#include <string>

#include "geometry/errors.h"
#include "geometry/instruction_set.h"
#include "renderer/image/partial_files.h"
#include "renderer/platform/version.h"

namespace isotrace {

namespace {
CLI::Validator finiteValidator(bool positive) {
    return CLI::Validator(
        [positive](std::string& text) -> std::string {
            double x = 0.0;
            size_t used = 0;
            try {
                x = std::stod(text, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used == 0 || used != text.size() || !std::isfinite(x)) return "expected a finite number, found " + text;
            if (positive && !(x > 0)) return "expected a number > 0, found " + text;
            return "";
        },
        positive ? "FINITE > 0" : "FINITE");
}
}  // namespace

CLI::Validator finitePositive() { return finiteValidator(true); }
CLI::Validator wholeNumber() {
    return CLI::Validator(
        [](std::string& text) -> std::string {
            const bool digits = !text.empty() && text.size() <= 20 &&
                                text.find_first_not_of("0123456789") == std::string::npos;
            if (!digits || (text.size() == 20 && text > "18446744073709551615"))
                return "expected a whole number from 0 to 2^64 - 1, found " + text;
            return "";
        },
        "UINT64");
}
CLI::Validator finiteNumber() { return finiteValidator(false); }

// The one place that maps an error's category (geometry/errors.h) to what
// the user reads and the exit status.
int runReportingErrors(const std::function<int()>& body) {
    try {
        return body();
    } catch (const geometry::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return kExitBadInput;
    } catch (const geometry::IoError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return kExitBadInput;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "error: not enough memory for this input\n");
        return kExitBadInput;
    } catch (const geometry::InternalError& e) {
        std::fprintf(stderr, "internal error: %s (a bug in isotrace %s; please report it with the command line)\n",
                     e.what(), kVersion);
        return kExitInternalError;
    } catch (const std::runtime_error& e) {
        // What the libraries isotrace reads files with report about them
        // (OpenImageIO, Assimp, OpenEXR): the input, not isotrace, is at fault.
        std::fprintf(stderr, "error: %s\n", e.what());
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "internal error: %s (a bug in isotrace %s; please report it with the command line)\n",
                     e.what(), kVersion);
        return kExitInternalError;
    } catch (...) {
        std::fprintf(stderr, "internal error: an unknown exception (a bug in isotrace %s)\n", kVersion);
        return kExitInternalError;
    }
}

int runIsotrace(int argc, const char* const* argv) {
    removePartialFilesOnSignal();
    // The cap on the vector kernels (geometry/instruction_set.h) is read from
    // the environment: a misspelt one is bad input, not silently ignored.
    if (const char* cap = std::getenv("ISOTRACE_MAX_ISA"); cap && *cap) {
        try {
            geometry::instructionSetNamed(cap);
        } catch (const std::invalid_argument& e) {
            std::fprintf(stderr, "error: ISOTRACE_MAX_ISA: %s\n", e.what());
            return kExitBadInput;
        }
    }
    CLI::App app{"isotrace: a physically based renderer for implicit surfaces"};
    app.set_version_flag("--version", std::string("isotrace ") + kVersion + " (numeric mode " + kNumericMode + ", " +
                                          std::string(geometry::instructionSetName(geometry::activeInstructionSet())) +
                                          " kernels)");
    app.require_subcommand(1);
    // Usage errors read like every other error: "error: " and the cause.
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return "error: " + std::string(e.what()) + "\nRun with --help for more information.\n";
    });
    const Subcommand commands[] = {addRenderCommand(app),  addPolygonizeCommand(app), addMergeCommand(app),
                                   addCompareCommand(app), addFitCommand(app),        addPreviewCommand(app), addSampleCommand(app),
                                   addVoxelizeCommand(app)};
    // CLI11 reports a misspelt command or an option before the command as
    // "a subcommand is required"; name what was typed instead.
    if (argc >= 2) {
        const std::string first = argv[1];
        const bool global = first == "-h" || first == "--help" || first == "--version";
        bool known = false;
        for (const Subcommand& c : commands) known = known || c.app->get_name() == first;
        if (!known && !global) {
            std::string names;
            for (const Subcommand& c : commands) names += (names.empty() ? "" : ", ") + c.app->get_name();
            std::fprintf(stderr, "error: %s \"%s\"; isotrace COMMAND [OPTIONS], where COMMAND is one of %s\n",
                         first.rfind('-', 0) == 0 ? "unknown option" : "unknown command", first.c_str(), names.c_str());
            return kExitBadInput;
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        app.exit(e);
        return kExitBadInput;
    }
    for (const Subcommand& c : commands)
        if (*c.app) return runReportingErrors(c.run);
    return kExitSuccess;
}

}  // namespace isotrace
