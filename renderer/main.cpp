// isotrace: the command line. Exit status 0 is success, 1 a comparison over
// its threshold, 2 bad input or usage.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include <tbb/task_arena.h>

#include "geometry/content_hash.h"
#include "geometry/field_parser.h"
#include "geometry/input_error.h"
#include "geometry/mesh_analysis.h"
#include "geometry/polygonizer.h"
#include "mesh_export.h"
#include "compare_command.h"
#include "csg_preview.h"
#include "fit_command.h"
#include "image_output.h"
#include "render.h"
#include "scene_loader.h"
#include "version.h"

using namespace isotrace;

namespace {

constexpr int kExitBadInput = 2;

struct RenderCommand {
    std::string scene;
    std::string output;
    int spp = 0, threads = 0, width = 0, height = 0;
    uint64_t seed = 0;
    bool quiet = false, half = false, noPreview = false;
    double exposure = 0.0;
    std::string as;
    std::vector<int> crop;  ///< x0 y0 x1 y1
    std::vector<std::string> aovs;
    std::string tile;       ///< "I/N"
};

// Tiles of one frame must come from the same scene text, wherever it was stored.
std::string sceneHash(const std::string& path) {
    uint64_t hash = geometry::kFnvOffsetBasis;
    geometry::fnv1a64File(path, hash);
    return geometry::hexDigest(hash);
}

// The window asked for by --crop or --tile, checked against the frame.
PixelWindow requestedWindow(const RenderCommand& cmd, int width, int height) {
    if (!cmd.crop.empty() && !cmd.tile.empty())
        throw geometry::InputError("command line", "", "give either --crop or --tile, not both");
    if (!cmd.crop.empty()) {
        const PixelWindow w{cmd.crop[0], cmd.crop[1], cmd.crop[2], cmd.crop[3]};
        if (w.x0 < 0 || w.y0 < 0 || w.x1 > width || w.y1 > height || w.empty())
            throw geometry::InputError("command line", "", "--crop " + std::to_string(w.x0) + " " + std::to_string(w.y0) + " " +
                                                   std::to_string(w.x1) + " " + std::to_string(w.y1) +
                                                   " is not a non-empty window of the " + std::to_string(width) + "x" +
                                                   std::to_string(height) + " frame (columns x0..x1, rows y0..y1, end excluded)");
        return w;
    }
    if (!cmd.tile.empty()) {
        int i = -1, n = 0;
        char slash = 0;
        std::istringstream in(cmd.tile);
        if (!(in >> i >> slash >> n) || slash != '/' || !in.eof() || n < 1 || i < 0 || i >= n || n > height)
            throw geometry::InputError("command line", "", "--tile takes I/N with 0 <= I < N <= image height, found \"" + cmd.tile + "\"");
        // Bands of whole rows, as even as the height allows.
        return {0, int(int64_t(i) * height / n), width, int(int64_t(i + 1) * height / n)};
    }
    return {};
}

std::string describeCamera(const CameraSettings& c) {
    std::ostringstream s;
    s << "perspective from (" << c.from.transpose() << ") to (" << c.to.transpose() << ") up (" << c.up.transpose()
      << ") fov " << c.verticalFovDegrees << " aperture " << c.aperture << " focus " << c.focusDistance;
    return s.str();
}


int runRender(const RenderCommand& cmd) {
    SceneOverrides overrides;
    overrides.width = cmd.width;
    overrides.height = cmd.height;
    overrides.samplesPerPixel = cmd.spp;
    if (cmd.as == "mesh") overrides.fieldMode = SceneOverrides::FieldMode::Mesh;
    if (cmd.as == "implicit") overrides.fieldMode = SceneOverrides::FieldMode::Implicit;
    const std::string output =
        cmd.output.empty() ? std::filesystem::path(cmd.scene).stem().string() + ".exr" : cmd.output;
    checkOutputFolder(output);

    // Loading builds surface cells and variational models in parallel: it
    // keeps to the same thread count as rendering.
    std::unique_ptr<Scene> scene;
    tbb::task_arena arena(cmd.threads > 0 ? cmd.threads : tbb::task_arena::automatic);
    arena.execute([&] { scene = loadScene(cmd.scene, overrides); });
    for (const std::string& w : scene->warnings) std::fprintf(stderr, "warning: %s: %s\n", cmd.scene.c_str(), w.c_str());
    RenderOptions options;
    options.crop = requestedWindow(cmd, scene->film.width, scene->film.height);
    options.aovs = cmd.aovs;
    options.threads = cmd.threads;
    options.seed = cmd.seed;
    options.quiet = cmd.quiet;
    RenderStatistics stats;
    const Image image = render(*scene, options, &stats);

    ImageMetadata meta;
    meta.strings = {{"Software", std::string("isotrace ") + kVersion},
                    {"isotrace:scene", cmd.scene},
                    {"isotrace:scene_hash", sceneHash(cmd.scene)},
                    {"isotrace:spp", std::to_string(scene->film.samplesPerPixel)},
                    {"isotrace:seed", std::to_string(cmd.seed)},
                    {"isotrace:render_seconds", std::to_string(stats.seconds)},
                    {"isotrace:camera", describeCamera(scene->camera)},
                    {"isotrace:integrator",
                     scene->integrator.type == IntegratorSettings::Type::Path ? "path" : "whitted"}};
    writeImage(output, image, meta, cmd.half);
    if (!cmd.noPreview) writePreviewPng(previewPathFor(output), image, cmd.exposure);
    if (stats.nonFiniteSamples > 0)
        std::fprintf(stderr, "warning: %lld samples had non-finite radiance and were discarded\n", stats.nonFiniteSamples);
    if (!cmd.quiet)
        std::fprintf(stderr, "wrote %s (%dx%d, %d spp) in %.2fs\n", output.c_str(), image.width, image.height,
                     scene->film.samplesPerPixel, stats.seconds);
    return 0;
}

struct PolygonizeCommand {
    std::string scene, field, output, method = "marching_cubes";
    int resolution = 0, threads = 0;
    double tolerance = 0.0;
    bool report = false;
};

int runPolygonize(const PolygonizeCommand& cmd) {
    if (!isMeshExtension(cmd.output))
        throw geometry::InputError(cmd.output, "", "unknown mesh format (use .ply, .obj or .off)");
    checkOutputFolder(cmd.output);
    const geometry::Json root = geometry::parseJsonFile(cmd.scene);
    if (!root.is_object() || !root.contains("fields"))
        throw geometry::InputError(cmd.scene, "/fields", "the scene has no \"fields\"");
    const geometry::FieldLibrary library(root.at("fields"), "/fields", cmd.scene);
    // Unknown names fail here, at "/fields", with the nearest name suggested.
    const geometry::FieldProgram field = library.compile(cmd.field);
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
            {"seconds", result.seconds},
        };
        std::printf("%s\n", report.dump(2).c_str());
    }
    return 0;
}

struct MergeCommand {
    std::vector<std::string> tiles;
    std::string output;
    bool half = false;
};

// Reassembles windows of one frame. They must come from the same scene,
// seed, sample count and frame size, and cover the frame exactly once.
int runMerge(const MergeCommand& cmd) {
    checkOutputFolder(cmd.output);
    Image full;
    ImageMetadata first;
    std::vector<int> owner;
    const char* mustMatch[] = {"isotrace:scene_hash", "isotrace:seed", "isotrace:spp", "isotrace:integrator"};
    for (size_t t = 0; t < cmd.tiles.size(); ++t) {
        const std::string& path = cmd.tiles[t];
        ImageMetadata meta;
        Image tile;
        try {
            tile = readImage(path, &meta);
        } catch (const std::exception& e) {
            throw geometry::InputError(path, "", e.what());
        }
        if (metadataValue(meta, "isotrace:seed").empty())
            throw geometry::InputError(path, "", "not an isotrace render (no isotrace metadata)");
        if (t == 0) {
            first = meta;
            full.width = full.fullWidth = tile.fullWidth;
            full.height = full.fullHeight = tile.fullHeight;
            full.rgb.assign(size_t(full.width) * full.height * 3, 0.0f);
            full.extraChannels = tile.extraChannels;
            full.extra.assign(size_t(full.width) * full.height * full.extraChannels.size(), 0.0f);
            owner.assign(size_t(full.width) * full.height, -1);
        } else {
            if (tile.fullWidth != full.width || tile.fullHeight != full.height)
                throw geometry::InputError(path, "", "frame size " + std::to_string(tile.fullWidth) + "x" +
                                                         std::to_string(tile.fullHeight) + " differs from " +
                                                         cmd.tiles[0] + "'s " + std::to_string(full.width) + "x" +
                                                         std::to_string(full.height));
            if (tile.extraChannels != full.extraChannels)
                throw geometry::InputError(path, "", "its channels differ from " + cmd.tiles[0] + "'s");
            for (const char* key : mustMatch)
                if (metadataValue(meta, key) != metadataValue(first, key))
                    throw geometry::InputError(path, "", std::string(key) + " is \"" + metadataValue(meta, key) + "\" but " +
                                                             cmd.tiles[0] + " has \"" + metadataValue(first, key) +
                                                             "\": tiles of different renders");
        }
        for (int y = 0; y < tile.height; ++y)
            for (int x = 0; x < tile.width; ++x) {
                const int fx = tile.x + x, fy = tile.y + y;
                if (fx < 0 || fy < 0 || fx >= full.width || fy >= full.height)
                    throw geometry::InputError(path, "", "its window lies outside the frame");
                int& o = owner[size_t(fy) * full.width + fx];
                if (o >= 0)
                    throw geometry::InputError(path, "", "overlaps " + cmd.tiles[o] + " at pixel (" + std::to_string(fx) +
                                                             ", " + std::to_string(fy) + ")");
                o = int(t);
                std::copy_n(tile.pixel(x, y), 3, full.pixel(fx, fy));
                if (!full.extraChannels.empty())
                    std::copy_n(tile.extraPixel(x, y), full.extraChannels.size(), full.extraPixel(fx, fy));
            }
    }
    for (size_t p = 0; p < owner.size(); ++p)
        if (owner[p] < 0)
            throw geometry::InputError(cmd.tiles[0], "", "the tiles do not cover the frame: pixel (" +
                                                             std::to_string(p % full.width) + ", " +
                                                             std::to_string(p / full.width) + ") is missing");
    writeImage(cmd.output, full, first, cmd.half);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"isotrace: a physically based renderer for implicit surfaces"};
    app.set_version_flag("--version", std::string("isotrace ") + kVersion);
    app.require_subcommand(1);

    RenderCommand render;
    CLI::App* renderApp = app.add_subcommand("render", "Render a scene file to an EXR (and a PNG preview)");
    renderApp->add_option("scene", render.scene, "Scene file (JSON)")->required();
    renderApp->add_option("-o,--output", render.output, "Output image (default: the scene's name with .exr)");
    renderApp->add_option("--spp", render.spp, "Samples per pixel (overrides the scene)")->check(CLI::Range(1, 1 << 20));
    renderApp->add_option("--threads", render.threads, "Worker threads for loading and rendering (default: all cores)")->check(CLI::Range(1, 4096));
    renderApp->add_option("--seed", render.seed, "Random seed");
    renderApp->add_option("--width", render.width, "Image width (overrides the scene)")->check(CLI::Range(1, 1 << 16));
    renderApp->add_option("--height", render.height, "Image height (overrides the scene)")->check(CLI::Range(1, 1 << 16));
    renderApp->add_option("--exposure", render.exposure, "Exposure of the PNG preview, in stops");
    renderApp->add_option("--as", render.as, "Render every field object as a mesh or as an implicit")
        ->check(CLI::IsMember({"mesh", "implicit"}));
    renderApp->add_flag("--half", render.half, "Write half-float EXR");
    renderApp->add_option("--crop", render.crop, "Render only columns X0..X1 and rows Y0..Y1 (end excluded)")
        ->expected(4)->type_name("X0 Y0 X1 Y1");
    renderApp->add_option("--aov", render.aovs, "Extra EXR layers: albedo, normal, depth, id, steps (comma separated)")
        ->delimiter(',')
        ->check(CLI::IsMember({"albedo", "normal", "depth", "id", "steps"}));
    renderApp->add_option("--tile", render.tile, "Render band I of N bands of rows (0 <= I < N), for isotrace merge")
        ->type_name("I/N");
    renderApp->add_flag("--no-preview", render.noPreview, "Do not write the PNG preview");
    renderApp->add_flag("-q,--quiet", render.quiet, "No progress output");

    PolygonizeCommand polygonize;
    CLI::App* polygonizeApp = app.add_subcommand("polygonize", "Turn a field of a scene into a triangle mesh (PLY, OBJ, OFF)");
    polygonizeApp->add_option("scene", polygonize.scene, "Scene file whose \"fields\" hold the field")->required();
    polygonizeApp->add_option("--field", polygonize.field, "Name of the field")->required();
    polygonizeApp->add_option("-o,--output", polygonize.output, "Output mesh: .ply (binary), .obj or .off")->required();
    polygonizeApp->add_option("--method", polygonize.method, "marching_cubes (uniform) or adaptive (sharp features, simplified)")
        ->check(CLI::IsMember({"marching_cubes", "adaptive"}));
    polygonizeApp->add_option("--resolution", polygonize.resolution, "Cells along the longest side of the bounds (default 128)")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()));
    polygonizeApp->add_option("--tolerance", polygonize.tolerance, "Largest distance of vertices and face centres to the surface")
        ->check(CLI::PositiveNumber);
    polygonizeApp->add_option("--threads", polygonize.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
    polygonizeApp->add_flag("--report", polygonize.report, "Print counts, topology and accuracy as JSON");

    MergeCommand merge;
    CLI::App* mergeApp = app.add_subcommand("merge", "Reassemble tiles (--crop/--tile renders) into the full frame");
    mergeApp->add_option("tiles", merge.tiles, "Tile EXRs")->required();
    mergeApp->add_option("-o,--output", merge.output, "The full frame")->required();
    mergeApp->add_flag("--half", merge.half, "Write half-float EXR");

    CompareCommand compare;
    addCompareCommand(app, compare);

    FitCommand fit;
    CLI::App* fitApp = app.add_subcommand(
        "fit", "Fit a variational implicit surface to a polygon model (OFF, OBJ, PLY) or oriented points (.xyz, .pwn)");
    fitApp->add_option("input", fit.input, "Polygon model or oriented point set (x y z nx ny nz per line)")->required();
    fitApp->add_option("-o,--output", fit.output, "The fitted field (JSON), for {\"type\": \"variational\", \"fitted\": ...}")
        ->required();
    fitApp->add_option("--normal-offset", fit.normalOffset,
                       "Distance of the normal constraints from the surface (default 0.01 of the bounding-box diagonal)")
        ->check(CLI::PositiveNumber);
    fitApp->add_flag("--hermite", fit.hermite, "Exact gradient constraints instead of offset normal constraints");
    fitApp->add_option("--margin", fit.margin, "Initial domain margin, a fraction of the bounding-box diagonal")
        ->check(CLI::PositiveNumber);
    fitApp->add_flag("-q,--quiet", fit.quiet, "No summary line");

    PreviewCommand preview;
    CLI::App* previewApp = app.add_subcommand(
        "preview", "Contact sheet of a CSG node: each operand, union, intersection and both differences");
    previewApp->add_option("scene", preview.scene, "Scene file whose \"fields\" hold the node")->required();
    previewApp->add_option("--field", preview.field, "Name of the CSG node")->required();
    previewApp->add_option("-o,--output", preview.output, "The sheet (default: SCENE-FIELD-preview.png)");
    previewApp->add_option("--section", preview.section,
                           "Show plane cuts coloured by the field's value instead: x, y or z, optionally =OFFSET")
        ->type_name("AXIS[=OFFSET]");
    previewApp->add_option("--panel-width", preview.panelWidth, "Width of each panel")->check(CLI::Range(16, 4096));
    previewApp->add_option("--panel-height", preview.panelHeight, "Height of each panel")->check(CLI::Range(16, 4096));
    previewApp->add_option("--spp", preview.spp, "Samples per pixel of each panel")->check(CLI::Range(1, 4096));
    previewApp->add_option("--threads", preview.threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
    previewApp->add_flag("-q,--quiet", preview.quiet, "No timing line");

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

    try {
        if (*renderApp) return runRender(render);
        if (*polygonizeApp) return runPolygonize(polygonize);
        if (*mergeApp) return runMerge(merge);
        if (app.got_subcommand("compare")) return runCompare(compare);
        if (*fitApp) {
            runFit(fit);
            return 0;
        }
        if (*previewApp) {
            runPreview(preview);
            return 0;
        }
    } catch (const geometry::InputError& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return kExitBadInput;
    }
    return 0;
}
