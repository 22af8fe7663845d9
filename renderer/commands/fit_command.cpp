// `isotrace fit`: an implicit surface through a polygon model or an
// oriented point set, saved so scenes load it without fitting again:
// variational ({"type": "variational", "fitted": "FIELD.json"}) or, with
// --method mpu, a multi-level partition of unity ({"type": "mpu", "fitted": ...}).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "geometry/atomic_file.h"
#include "geometry/errors.h"
#include "geometry/description/field_parser.h"
#include "geometry/description/mpu_description.h"
#include "geometry/description/variational_description.h"
#include "geometry/mesh_file.h"
#include "geometry/meshing/mesh_distance.h"
#include "geometry/meshing/polygonizer.h"
#include "geometry/variational/constraints.h"
#include "renderer/commands/command.h"
#include "renderer/image/image_output.h"

namespace isotrace {

namespace {

using geometry::InputError;
using geometry::Json;

struct FitCommand {
    std::string input, output;
    std::string method = "variational";
    double normalOffset = 0.0;  ///< 0: 0.01 of the bounding-box diagonal
    bool hermite = false;
    double margin = 0.0;        ///< 0: the default domain margin
    std::string solver;         ///< empty: "auto"
    // MPU options; unset: the defaults of the scene format.
    std::optional<double> accuracy, support;
    std::optional<int> maxDepth, minPoints;
    bool smoothOnly = false;
    bool quiet = false;
    bool report = false;
    int reportResolution = 128;
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

void writeFit(const std::string& output, const std::string& text) {
    try {
        geometry::writeFileAtomically(output, text);
    } catch (const std::runtime_error& e) {
        throw InputError(output, "", e.what());
    }
}

int runMpuFit(const FitCommand& c, const Json& description, geometry::VariationalContext& context, bool points) {
    geometry::JsonObjectReader reader(description, "", "command line");
    reader.string("type");
    geometry::MpuSource source;
    try {
        source = geometry::readMpuSource(reader, context);
    } catch (const InputError& e) {
        throw commandLineError(e, c.input, std::filesystem::absolute(c.input).string());
    }
    geometry::MpuReport report;
    const geometry::MpuField field =
        geometry::fitMpuSource(source, geometry::JsonObjectReader(description, "", c.input), report,
                               [&](const std::string& message) { context.warn("", "", message); });
    Json provenance = source.provenance;
    provenance[points ? "points" : "mesh"]["file"] = c.input;
    writeFit(c.output, geometry::mpuFieldToJson(field, report, provenance, source.hash).dump() + "\n");
    if (!c.quiet)
        std::fprintf(stderr, "fitted %zu oriented points with %zu local functions (%zu edges, %zu corners, depth %d) in %.3fs; "
                             "worst point %.3g, mean %.2g of the diagonal; wrote %s\n",
                     source.points.size(), report.localFunctions, report.edges, report.corners, report.depth,
                     report.seconds, report.maxError, report.meanError, c.output.c_str());
    return kExitSuccess;
}

Json topologyOf(const geometry::IndexedMesh& mesh) {
    const std::vector<geometry::MeshComponent> components = geometry::meshComponents(mesh);
    Json genus = Json::array();
    bool closed = !components.empty();
    for (const geometry::MeshComponent& component : components) {
        closed = closed && component.closed;
        genus.push_back(component.genus());
    }
    return {{"closed", closed}, {"components", components.size()}, {"genus", genus}};
}

// What a user sees of a fit: the fitted field polygonized, its distance to
// the input both ways (over the input's bounding diagonal), whether it is
// closed, and its components and their genus beside the input's.
Json fitQualityReport(const FitCommand& c, bool points) {
    geometry::IndexedMesh input;
    if (points) {
        for (const geometry::OrientedPoint& p : geometry::readOrientedPoints(c.input)) input.vertices.push_back(p.position);
    } else {
        input = geometry::readMeshFile(c.input);
        geometry::weldCoincidentVertices(input);
    }
    geometry::Box3 box;
    for (const geometry::Vec3& v : input.vertices) box.extend(v);
    const double diagonal = box.extent().norm();
    const Json fields = {{"fit", {{"type", c.method}, {"fitted", std::filesystem::absolute(c.output).string()}}}};
    const geometry::FieldProgram field = geometry::FieldLibrary(fields, "/fields", c.output).compile("fit");
    geometry::PolygonizeOptions options;
    options.resolution = c.reportResolution;
    const geometry::Polygonization fitted = geometry::polygonize(field, options);
    Json report = {{"resolution", c.reportResolution}, {"diagonal", diagonal}, {"fit", topologyOf(fitted.mesh)}};
    if (!points) report["input"] = topologyOf(input);
    if (fitted.mesh.triangles.empty()) {
        report["fit"]["closed"] = false;
        return report;
    }
    const geometry::NearestSurface fitSurface(fitted.mesh), inputSurface(input);
    const geometry::DistanceSummary inputToFit = geometry::distancesTo(fitSurface, input.vertices);
    const geometry::DistanceSummary fitToInput = geometry::distancesTo(inputSurface, fitted.mesh.vertices);
    auto summary = [&](const geometry::DistanceSummary& d) {
        Json j;
        j["mean"] = d.mean / diagonal;
        j["max"] = d.max / diagonal;
        return j;
    };
    Json distance;
    distance["input_to_fit"] = summary(inputToFit);
    distance["fit_to_input"] = summary(fitToInput);
    distance["mean"] = 0.5 * (inputToFit.mean + fitToInput.mean) / diagonal;
    distance["max"] = std::max(inputToFit.max, fitToInput.max) / diagonal;
    report["distance"] = distance;
    return report;
}

// Bad input (unreadable or malformed files, singular systems, too many
// constraints) throws geometry::InputError; nothing is written then.
int runFit(const FitCommand& c) {
    checkOutputPath(c.output, {c.input});
    const bool mpu = c.method == "mpu";
    if (!mpu && (c.accuracy || c.support || c.maxDepth || c.minPoints || c.smoothOnly))
        throw InputError("command line", "--method", "--accuracy, --support, --max-depth, --min-points and --smooth-only "
                                                     "are options of --method mpu");
    if (mpu && (c.normalOffset > 0 || c.hermite || c.margin > 0 || !c.solver.empty()))
        throw InputError("command line", "--method",
                         "--normal-offset, --hermite, --margin and --solver are options of --method variational");
    // The command line becomes a description, so files and keys are read
    // exactly as in scene files.
    const bool points = geometry::isOrientedPointFile(c.input);
    Json description = {{"type", c.method}, {points ? "points" : "mesh", std::filesystem::absolute(c.input).string()}};
    if (c.normalOffset > 0) description["normal_offset"] = c.normalOffset;
    if (c.hermite) description["hermite"] = true;
    if (c.margin > 0) description["margin"] = c.margin;
    if (!c.solver.empty()) description["solver"] = c.solver;
    if (c.accuracy) description["accuracy"] = *c.accuracy;
    if (c.support) description["support"] = *c.support;
    if (c.maxDepth) description["max_depth"] = *c.maxDepth;
    if (c.minPoints) description["min_points"] = *c.minPoints;
    if (c.smoothOnly) description["sharp_features"] = false;
    // Errors inside the input file name it and the line.
    geometry::VariationalContext context;
    context.warn = [&](const std::string&, const std::string&, const std::string& message) {
        std::fprintf(stderr, "warning: %s: %s\n", c.input.c_str(), message.c_str());
    };
    if (mpu) {
        const int status = runMpuFit(c, description, context, points);
        if (c.report) std::printf("%s\n", fitQualityReport(c, points).dump(2).c_str());
        return status;
    }
    geometry::JsonObjectReader reader(description, "", "command line");
    reader.string("type");
    geometry::VariationalSource source;
    try {
        source = geometry::readVariationalSource(reader, context);
    } catch (const InputError& e) {
        throw commandLineError(e, c.input, std::filesystem::absolute(c.input).string());
    }
    // Keep the input's name as given, not the absolute path used to read it.
    Json provenance = source.provenance;
    provenance[points ? "points" : "mesh"]["file"] = c.input;
    if (source.partitioned()) {
        geometry::PartitionReport report;
        geometry::MpuField field;
        try {
            field = geometry::fitPartitionedVariationalField(source.constraints, &report, source.partitionOptions());
        } catch (const geometry::FitError& e) {
            throw InputError(c.input, "", e.what());
        }
        writeFit(c.output,
                 geometry::mpuFieldToJson(field, geometry::partitionSummary(report), provenance, source.hash).dump() + "\n");
        for (const std::string& w : report.warnings) std::fprintf(stderr, "warning: %s: %s\n", c.input.c_str(), w.c_str());
        if (!c.quiet)
            std::fprintf(stderr, "fitted %zu constraints by a partition of %zu local interpolants (%.0f constraints each, "
                                 "at most %zu) in %.3fs; max residual %.3g; wrote %s\n",
                         report.constraints, report.locals, report.meanLocal, report.largestLocal, report.seconds,
                         report.maxResidual, c.output.c_str());
        if (c.report) std::printf("%s\n", fitQualityReport(c, points).dump(2).c_str());
        return kExitSuccess;
    }
    geometry::FitReport report;
    geometry::VariationalField field;
    try {
        field = geometry::fitVariationalField(source.constraints, &report, source.options);
    } catch (const geometry::FitError& e) {
        throw InputError(c.input, "", e.what());
    }
    writeFit(c.output, geometry::variationalFieldToJson(field, report, provenance, source.hash).dump() + "\n");
    for (const std::string& w : report.warnings) std::fprintf(stderr, "warning: %s: %s\n", c.input.c_str(), w.c_str());
    if (!c.quiet)
        std::fprintf(stderr, "fitted %zu value and %zu gradient constraints (%zu unknowns) in %.3fs; max residual %.3g, "
                             "reciprocal condition %.3g; wrote %s\n",
                     field.centers.size(), field.gradientCenters.size(), report.unknowns, report.seconds,
                     report.maxResidual, report.reciprocalCondition, c.output.c_str());
    if (c.report) std::printf("%s\n", fitQualityReport(c, points).dump(2).c_str());
    return kExitSuccess;
}

}  // namespace

Subcommand addFitCommand(CLI::App& app) {
    auto c = std::make_shared<FitCommand>();
    CLI::App* sub = app.add_subcommand(
        "fit", "Fit an implicit surface (variational, or multi-level partition of unity) to a polygon model (OFF, OBJ, PLY) "
               "or oriented points (.xyz, .pwn, .pts)");
    sub->add_option("input", c->input, "Polygon model or oriented point set (x y z nx ny nz per line)")->required();
    sub->add_option("-o,--output", c->output,
                    "The fitted field (JSON), for {\"type\": \"variational\" (or \"mpu\"), \"fitted\": ...}")
        ->required();
    sub->add_option("--method", c->method,
                    "variational (exact interpolation) or mpu (local quadric fits within an accuracy, for large scans)")
        ->check(CLI::IsMember({"variational", "mpu"}))
        ->capture_default_str();
    sub->add_option("--solver", c->solver,
                    "variational: dense (one interpolant), partition (local interpolants blended, any size) or auto "
                    "(dense up to 20,000 unknowns; the default)")
        ->check(CLI::IsMember({"auto", "dense", "partition"}));
    sub->add_option("--normal-offset", c->normalOffset,
                       "Distance of the normal constraints from the surface (default 0.01 of the bounding-box diagonal)")
        ->check(finitePositive());
    sub->add_flag("--hermite", c->hermite, "Exact gradient constraints instead of offset normal constraints");
    sub->add_option("--margin", c->margin, "Initial domain margin, a fraction of the bounding-box diagonal")
        ->check(finitePositive());
    sub->add_option("--accuracy", c->accuracy, "mpu: largest distance of the points to their local fits, over the diagonal (0.002)")
        ->check(CLI::Range(1e-9, 0.999999));
    sub->add_option("--support", c->support, "mpu: ball radius over cell diagonal, in (0.5, 4] (0.75)");
    sub->add_option("--max-depth", c->maxDepth, "mpu: octree levels, 1 to 20 (10)")->check(CLI::Range(1, 20));
    sub->add_option("--min-points", c->minPoints, "mpu: points a ball must hold, 6 to 1,000 (15)")->check(CLI::Range(6, 1000));
    sub->add_flag("--smooth-only", c->smoothOnly, "mpu: no edge and corner functions (sharp features round off)");
    sub->add_flag("-q,--quiet", c->quiet, "No summary line");
    CLI::Option* report = sub->add_flag(
        "--report", c->report, "Print JSON: the fit polygonized, its distance to the input both ways, closedness, components and genus");
    sub->add_option("--report-resolution", c->reportResolution, "Cells along the longest side for --report (128)")
        ->check(CLI::Range(8, 1024))
        ->needs(report);
    return {sub, [c] { return runFit(*c); }};
}

}  // namespace isotrace
