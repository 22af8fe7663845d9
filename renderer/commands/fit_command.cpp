// `isotrace fit`: a variational implicit surface through a polygon model or
// an oriented point set, saved so scenes load it without solving again
// ({"type": "variational", "fitted": "FIELD.json"}).

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "geometry/description/variational_description.h"
#include "renderer/commands/command.h"
#include "renderer/image_output.h"

namespace isotrace {

namespace {

using geometry::InputError;
using geometry::Json;

struct FitCommand {
    std::string input, output;
    double normalOffset = 0.0;  ///< 0: 0.01 of the bounding-box diagonal
    bool hermite = false;
    double margin = 0.0;        ///< 0: the default domain margin
    bool quiet = false;
};

// Errors about the description the command line became, said in the
// user's terms: the input file as typed (not "command line: /mesh: /abs/path")
// and options by their flags.
InputError commandLineError(const InputError& e, const std::string& input, const std::string& absoluteInput) {
    if (e.where() == "/mesh" || e.where() == "/points") {
        std::string message = e.message();
        const std::string prefix = absoluteInput + ": ";
        if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
        // The reader's own place in the file (a line) stays in the message.
        return InputError(input, "", message);
    }
    std::string flag = e.where();
    if (!flag.empty() && flag[0] == '/') flag = "--" + flag.substr(1);
    std::replace(flag.begin(), flag.end(), '_', '-');
    return InputError("command line", flag, e.message());
}

// Bad input (unreadable or malformed files, singular systems, too many
// constraints) throws geometry::InputError; nothing is written then.
int runFit(const FitCommand& c) {
    checkOutputPath(c.output, {c.input});
    // The command line becomes a description, so files and keys are read
    // exactly as in scene files.
    const bool points = geometry::isOrientedPointFile(c.input);
    Json description = {{"type", "variational"}, {points ? "points" : "mesh", std::filesystem::absolute(c.input).string()}};
    if (c.normalOffset > 0) description["normal_offset"] = c.normalOffset;
    if (c.hermite) description["hermite"] = true;
    if (c.margin > 0) description["margin"] = c.margin;
    geometry::JsonObjectReader reader(description, "", "command line");
    reader.string("type");
    // Errors inside the input file name it and the line.
    geometry::VariationalContext context;
    context.warn = [&](const std::string&, const std::string&, const std::string& message) {
        std::fprintf(stderr, "warning: %s: %s\n", c.input.c_str(), message.c_str());
    };
    geometry::VariationalSource source;
    try {
        source = geometry::readVariationalSource(reader, context);
    } catch (const InputError& e) {
        throw commandLineError(e, c.input, std::filesystem::absolute(c.input).string());
    }
    geometry::FitReport report;
    geometry::VariationalField field;
    try {
        field = geometry::fitVariationalField(source.constraints, &report, source.options);
    } catch (const geometry::FitError& e) {
        throw InputError(c.input, "", e.what());
    }
    // Keep the input's name as given, not the absolute path used to read it.
    Json provenance = source.provenance;
    provenance[points ? "points" : "mesh"]["file"] = c.input;
    const std::string text = geometry::variationalFieldToJson(field, report, provenance, source.hash).dump() + "\n";

    try {
        geometry::writeFileAtomically(c.output, text);
    } catch (const std::runtime_error& e) {
        throw InputError(c.output, "", e.what());
    }
    for (const std::string& w : report.warnings) std::fprintf(stderr, "warning: %s: %s\n", c.input.c_str(), w.c_str());
    if (!c.quiet)
        std::fprintf(stderr, "fitted %zu value and %zu gradient constraints (%zu unknowns) in %.3fs; max residual %.3g, "
                             "reciprocal condition %.3g; wrote %s\n",
                     field.centers.size(), field.gradientCenters.size(), report.unknowns, report.seconds,
                     report.maxResidual, report.reciprocalCondition, c.output.c_str());
    return kExitSuccess;
}

}  // namespace

Subcommand addFitCommand(CLI::App& app) {
    auto c = std::make_shared<FitCommand>();
    CLI::App* sub = app.add_subcommand(
        "fit", "Fit a variational implicit surface to a polygon model (OFF, OBJ, PLY) or oriented points (.xyz, .pwn, .pts)");
    sub->add_option("input", c->input, "Polygon model or oriented point set (x y z nx ny nz per line)")->required();
    sub->add_option("-o,--output", c->output, "The fitted field (JSON), for {\"type\": \"variational\", \"fitted\": ...}")
        ->required();
    sub->add_option("--normal-offset", c->normalOffset,
                       "Distance of the normal constraints from the surface (default 0.01 of the bounding-box diagonal)")
        ->check(finitePositive());
    sub->add_flag("--hermite", c->hermite, "Exact gradient constraints instead of offset normal constraints");
    sub->add_option("--margin", c->margin, "Initial domain margin, a fraction of the bounding-box diagonal")
        ->check(finitePositive());
    sub->add_flag("-q,--quiet", c->quiet, "No summary line");
    return {sub, [c] { return runFit(*c); }};
}

}  // namespace isotrace
