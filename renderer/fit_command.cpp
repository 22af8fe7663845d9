#include "fit_command.h"

#include <cstdio>
#include <filesystem>

#include "geometry/atomic_file.h"
#include "geometry/input_error.h"
#include "geometry/variational/variational_description.h"
#include "image_output.h"

namespace isotrace {

using geometry::InputError;
using geometry::Json;

void runFit(const FitCommand& c) {
    checkOutputFolder(c.output);
    // The command line becomes a description, so files and keys are read
    // exactly as in scene files.
    const std::string extension = std::filesystem::path(c.input).extension().string();
    const bool points = extension == ".xyz" || extension == ".pwn" || extension == ".pts";
    Json description = {{"type", "variational"}, {points ? "points" : "mesh", std::filesystem::absolute(c.input).string()}};
    if (c.normalOffset > 0) description["normal_offset"] = c.normalOffset;
    if (c.hermite) description["hermite"] = true;
    if (c.margin > 0) description["margin"] = c.margin;
    geometry::JsonObjectReader reader(description, "", "command line");
    reader.string("type");
    // Errors inside the input file name it and the line.
    geometry::VariationalContext context;
    const geometry::VariationalSource source = geometry::readVariationalSource(reader, context);
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
}

}  // namespace isotrace
