// `isotrace polygonize`: a field of a scene to a triangle mesh file, with an
// optional report of its topology and accuracy.
#include <cstdio>
#include <limits>

#include "geometry/description/field_parser.h"
#include "geometry/errors.h"
#include "geometry/meshing/mesh_analysis.h"
#include "geometry/meshing/polygonizer.h"
#include "renderer/commands/command.h"
#include "renderer/field_hosting.h"
#include "renderer/image/image_output.h"
#include "renderer/mesh_export.h"
#include "renderer/scene_loader.h"

namespace isotrace {

namespace {

struct PolygonizeCommand {
    std::string scene, field, output, method = "marching_cubes";
    int resolution = 0, threads = 0;
    double tolerance = 0.0;
    bool report = false;
};

int runPolygonize(const PolygonizeCommand& cmd) {
    if (!isMeshExtension(cmd.output))
        throw geometry::InputError(cmd.output, "", "unknown mesh format (use .ply, .obj or .off)");
    checkOutputPath(cmd.output, sceneInputFiles(cmd.scene));
    // Unknown names fail here, at "/fields", with the nearest name suggested.
    const geometry::FieldProgram field = compileSceneField(cmd.scene, cmd.field);
    geometry::PolygonizeOptions options;
    options.method = cmd.method == "adaptive" ? geometry::PolygonizeMethod::Adaptive
                                              : geometry::PolygonizeMethod::MarchingCubes;
    options.resolution = cmd.resolution;
    options.tolerance = cmd.tolerance;
    options.threads = cmd.threads;
    geometry::Polygonization result;
    try {
        result = geometry::polygonize(field, options);
    } catch (const std::invalid_argument& e) {
        throw geometry::InputError(cmd.scene, geometry::jsonPointerAppend("/fields", cmd.field), e.what());
    }
    for (const std::string& w : result.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    writeMesh(cmd.output, result.mesh);
    if (cmd.report) {
        const geometry::MeshTopology t = geometry::analyzeTopology(result.mesh);
        const geometry::MeshAccuracy a = geometry::measureAccuracy(result.mesh, field);
        const geometry::Json report = {
            {"field", cmd.field},
            {"method", cmd.method},
            {"resolution", result.resolution},
            {"extraction_resolution", result.extractionResolution},
            {"triangles", t.triangles},
            {"vertices", t.vertices},
            {"watertight", t.watertight()},
            {"manifold", t.manifold()},
            {"consistently_oriented", t.oriented()},
            {"euler_characteristic", t.eulerCharacteristic},
            {"max_vertex_distance", a.maxVertexDistance},
            {"mean_vertex_distance", a.meanVertexDistance},
            {"max_centroid_distance", a.maxCentroidDistance},
            {"mean_centroid_distance", a.meanCentroidDistance},
            {"max_normal_deviation_degrees", a.maxNormalDeviationDegrees},
            {"mean_normal_deviation_degrees", a.meanNormalDeviationDegrees},
            {"worst_aspect_ratio", a.worstAspectRatio},
            {"aspect_ratio_99th_percentile", a.aspectRatio99thPercentile},
            {"seconds", result.seconds},
            // Where the adaptive mesher's time went (marching cubes: all in extraction).
            {"extraction_seconds", result.extractionSeconds},
            {"refinement_seconds", result.refinementSeconds},
            {"simplification_seconds", result.simplificationSeconds},
        };
        std::printf("%s\n", report.dump(2).c_str());
    }
    return 0;
}

}  // namespace

Subcommand addPolygonizeCommand(CLI::App& app) {
    auto c = std::make_shared<PolygonizeCommand>();
    CLI::App* sub = app.add_subcommand("polygonize", "Turn a field of a scene into a triangle mesh (PLY, OBJ, OFF)");
    sub->add_option("scene", c->scene, "Scene file whose \"fields\" hold the field")->required();
    sub->add_option("--field", c->field, "Name of the field")->required();
    sub->add_option("-o,--output", c->output, "Output mesh: .ply (binary), .obj or .off")->required();
    sub->add_option("--method", c->method, "marching_cubes (uniform) or adaptive (sharp features, simplified)")
        ->check(CLI::IsMember({"marching_cubes", "adaptive"}));
    sub->add_option("--resolution", c->resolution, "Cells along the longest side of the bounds (default 128)")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()));
    sub->add_option("--tolerance", c->tolerance, "Largest distance of vertices and face centres to the surface")
        ->check(finitePositive());
    sub->add_option("--threads", c->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
    sub->add_flag("--report", c->report, "Print counts, topology and accuracy as JSON");
    return {sub, [c] { return runPolygonize(*c); }};
}

}  // namespace isotrace
