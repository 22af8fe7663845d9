// `isotrace render`: a scene file to an EXR and a PNG preview, whole or as
// a crop or tile of the frame.
#include <cstdio>
#include <exception>
#include <filesystem>
#include <sstream>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "geometry/content_hash.h"
#include "geometry/errors.h"
#include "geometry/instruction_set.h"
#include "geometry/mesh_file.h"
#include "renderer/commands/command.h"
#include "renderer/image/image_output.h"
#include "renderer/integrator.h"
#include "renderer/render.h"
#include "renderer/scene_loader.h"
#include "renderer/platform/version.h"

namespace isotrace {

namespace {

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


// The image (an EXR's last band, late header value and rename, or a whole
// file of another format) and its preview are written at once, each mostly
// on one thread. A failed image takes its preview with it, so no
// half-finished pair is left.
void writeImageAndPreview(tbb::task_arena& arena, const RenderCommand& cmd, const std::string& output,
                          const std::function<void()>& writeOutput, const Image& image) {
    std::exception_ptr imageError, previewError;
    arena.execute([&] {
        tbb::parallel_invoke(
            [&] {
                try {
                    writeOutput();
                } catch (...) {
                    imageError = std::current_exception();
                }
            },
            [&] {
                try {
                    if (!cmd.noPreview) writePreviewPng(previewPathFor(output), image, cmd.exposure);
                } catch (...) {
                    previewError = std::current_exception();
                }
            });
    });
    if (imageError) {
        std::error_code ignored;
        if (!cmd.noPreview && !previewError) std::filesystem::remove(previewPathFor(output), ignored);
        std::rethrow_exception(imageError);
    }
    if (previewError) std::rethrow_exception(previewError);
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
    if (cmd.half && geometry::lowercaseExtension(output) != ".exr")
        throw geometry::InputError("command line", "--half", "half floats are written to EXR only, not to " + output);
    std::vector<std::string> inputs = sceneInputFiles(cmd.scene);
    checkOutputPath(output, inputs);
    inputs.push_back(output);
    if (!cmd.noPreview) checkOutputPath(previewPathFor(output), inputs);

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
    ImageMetadata meta;
    meta.strings = {{"Software", std::string("isotrace ") + kVersion},
                    {"isotrace:version", kVersion},
                    {"isotrace:numeric_mode", kNumericMode},
                    {"isotrace:instruction_set",
                     std::string(geometry::instructionSetName(geometry::activeInstructionSet()))},
                    {"isotrace:scene", cmd.scene},
                    {"isotrace:scene_hash", sceneHash(cmd.scene)},
                    {"isotrace:spp", std::to_string(scene->film.samplesPerPixel)},
                    {"isotrace:seed", std::to_string(cmd.seed)},
                    {"isotrace:camera", describeCamera(scene->camera)},
                    {"isotrace:integrator", scene->integrator->typeName()}};
    // An EXR is compressed band by band as the render finishes rows; its
    // render time, known last, has a width kept for it in the header.
    const char* const kRenderSeconds = "isotrace:render_seconds";
    std::unique_ptr<RenderExrWriter> exr;
    if (geometry::lowercaseExtension(output) == ".exr") {
        const std::vector<std::pair<std::string, size_t>> late = {{kRenderSeconds, 16}};
        exr = std::make_unique<RenderExrWriter>(output, meta, cmd.half, late);
        options.rowsFinished = [&](const Image& image, int end) { exr->rowsFinished(image, end); };
    }
    RenderStatistics stats;
    const Image image = render(*scene, options, &stats);
    const std::string seconds = std::to_string(stats.seconds);
    auto writeOutput = [&] {
        if (exr) {
            exr->finish(image, {{kRenderSeconds, seconds}});
        } else {
            meta.strings.emplace_back(kRenderSeconds, seconds);
            writeImage(output, image, meta, cmd.half);
        }
    };
    writeImageAndPreview(arena, cmd, output, writeOutput, image);
    if (stats.nonFiniteSamples > 0)
        std::fprintf(stderr, "warning: %lld samples had non-finite radiance and were discarded\n", stats.nonFiniteSamples);
    if (!cmd.quiet)
        std::fprintf(stderr, "wrote %s (%dx%d, %d spp) in %.2fs\n", output.c_str(), image.width, image.height,
                     scene->film.samplesPerPixel, stats.seconds);
    return 0;
}

}  // namespace

Subcommand addRenderCommand(CLI::App& app) {
    auto c = std::make_shared<RenderCommand>();
    CLI::App* sub = app.add_subcommand("render", "Render a scene file to an EXR (and a PNG preview)");
    sub->add_option("scene", c->scene, "Scene file (JSON)")->required();
    sub->add_option("-o,--output", c->output, "Output image (default: the scene's name with .exr)");
    sub->add_option("--spp", c->spp, "Samples per pixel (overrides the scene)")->check(CLI::Range(1, 1 << 20));
    sub->add_option("--threads", c->threads, "Worker threads for loading and rendering (default: all cores)")->check(CLI::Range(1, 4096));
    sub->add_option("--seed", c->seed, "Random seed (a whole number >= 0)")->check(wholeNumber());
    sub->add_option("--width", c->width, "Image width (overrides the scene)")->check(CLI::Range(1, 1 << 16));
    sub->add_option("--height", c->height, "Image height (overrides the scene)")->check(CLI::Range(1, 1 << 16));
    sub->add_option("--exposure", c->exposure, "Exposure of the PNG preview, in stops")->check(finiteNumber());
    sub->add_option("--as", c->as, "Render every field object as a mesh or as an implicit")
        ->check(CLI::IsMember({"mesh", "implicit"}));
    sub->add_flag("--half", c->half, "Write half-float EXR");
    sub->add_option("--crop", c->crop, "Render only columns X0..X1 and rows Y0..Y1 (end excluded)")
        ->expected(4)->type_name("X0 Y0 X1 Y1");
    sub->add_option("--aov", c->aovs, "Extra EXR layers: albedo, normal, depth, id, steps (comma separated)")
        ->delimiter(',')
        ->check(CLI::IsMember({"albedo", "normal", "depth", "id", "steps"}));
    sub->add_option("--tile", c->tile, "Render band I of N bands of rows (0 <= I < N), for isotrace merge")
        ->type_name("I/N");
    sub->add_flag("--no-preview", c->noPreview, "Do not write the PNG preview");
    sub->add_flag("-q,--quiet", c->quiet, "No progress output");
    return {sub, [c] { return runRender(*c); }};
}

}  // namespace isotrace
