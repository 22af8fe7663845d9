// `isotrace sample`: particles spread evenly over a field of a scene
// (Witkin and Heckbert), written as oriented points, with an optional
// report of how close and how even they are.
#include <chrono>
#include <cstdio>

#include "geometry/description/field_parser.h"
#include "geometry/errors.h"
#include "geometry/particles/surface_particles.h"
#include "renderer/commands/command.h"
#include "renderer/field_hosting.h"
#include "renderer/image/image_output.h"
#include "renderer/point_export.h"
#include "renderer/scene_loader.h"

namespace isotrace {

namespace {

struct SampleCommand {
    std::string scene, field, output;
    size_t count = 0;
    double spacing = 0.0;
    uint64_t seed = 1;
    int threads = 0;
    bool report = false;
};

int runSample(const SampleCommand& cmd) {
    if (!isPointSetExtension(cmd.output))
        throw geometry::InputError(cmd.output, "", "unknown point set format (use .ply or .xyz)");
    if ((cmd.count > 0) == (cmd.spacing > 0))
        throw geometry::InputError("command line", "", "give one of --count and --spacing");
    checkOutputPath(cmd.output, sceneInputFiles(cmd.scene));
    const geometry::FieldProgram field = compileSceneField(cmd.scene, cmd.field);
    geometry::ParticleOptions options;
    options.count = cmd.count;
    options.spacing = cmd.spacing;
    options.seed = cmd.seed;
    options.threads = cmd.threads;
    const auto start = std::chrono::steady_clock::now();
    geometry::ParticleSampling result;
    try {
        result = geometry::spreadParticles(field, options);
    } catch (const std::invalid_argument& e) {
        throw geometry::InputError(cmd.scene, geometry::jsonPointerAppend("/fields", cmd.field), e.what());
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    writePoints(cmd.output, result.particles);
    if (cmd.report) {
        const geometry::ParticleStatistics s = geometry::measureParticles(field, result.particles);
        const geometry::Json report = {
            {"field", cmd.field},
            {"count", result.particles.size()},
            {"spacing", result.spacing},
            {"area", result.area},
            {"max_distance", s.maxDistance},
            {"mean_distance", s.meanDistance},
            {"nearest_neighbour_mean", s.nearestMean},
            {"nearest_neighbour_variation", s.nearestVariation},
            {"components", result.componentCounts},
            {"fissions", result.fissions},
            {"deaths", result.deaths},
            {"seconds", seconds},
        };
        std::printf("%s\n", report.dump(2).c_str());
    }
    return 0;
}

}  // namespace

Subcommand addSampleCommand(CLI::App& app) {
    auto c = std::make_shared<SampleCommand>();
    CLI::App* sub = app.add_subcommand("sample", "Spread particles evenly over a field of a scene (oriented points: PLY, XYZ)");
    sub->add_option("scene", c->scene, "Scene file whose \"fields\" hold the field")->required();
    sub->add_option("--field", c->field, "Name of the field")->required();
    sub->add_option("-o,--output", c->output, "Output points: .ply (binary, with radius) or .xyz (text)")->required();
    auto* count = sub->add_option("--count", c->count, "About how many particles (1 to 10,000,000)")
                      ->check(CLI::Range(size_t(1), size_t(10000000)));
    auto* spacing = sub->add_option("--spacing", c->spacing, "Distance between neighbours")->check(finitePositive());
    count->excludes(spacing);
    sub->add_option("--seed", c->seed, "Random seed: the same seed gives the same points on any thread count")
        ->check(wholeNumber());
    sub->add_option("--threads", c->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
    sub->add_flag("--report", c->report, "Print count, distance to the surface, evenness and components as JSON");
    return {sub, [c] { return runSample(*c); }};
}

}  // namespace isotrace
