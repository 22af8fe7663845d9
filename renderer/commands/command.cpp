#include "renderer/commands/command.h"

#include <cstdio>
#include <new>
#include <stdexcept>
#include <string>

#include "geometry/input_error.h"
#include "renderer/version.h"

namespace isotrace {

int runReportingErrors(const std::function<int()>& body) {
    try {
        return body();
    } catch (const geometry::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return kExitBadInput;
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "error: not enough memory for this input\n");
        return kExitBadInput;
    } catch (const std::runtime_error& e) {
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
    CLI::App app{"isotrace: a physically based renderer for implicit surfaces"};
    app.set_version_flag("--version", std::string("isotrace ") + kVersion);
    app.require_subcommand(1);
    const Subcommand commands[] = {addRenderCommand(app),  addPolygonizeCommand(app), addMergeCommand(app),
                                   addCompareCommand(app), addFitCommand(app),        addPreviewCommand(app)};
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
