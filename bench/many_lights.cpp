// Many lights (#64): a sphere on a floor under n small quad lights of the
// same total power, path traced at 320x240 and 16 spp on 2 threads, with
// the light tree and with the exhaustive walk of every light's importance.
// Prints the time per sample against one light, and at 1,000 lights each
// sampler's efficiency 1 / (RMSE^2 t) against a 512-spp reference.
#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench_support.h"
#include "geometry/description/field_parser.h"
#include "renderer/render.h"
#include "renderer/scene_builder.h"

using namespace isotrace;

namespace {

constexpr int kWidth = 320, kHeight = 240, kSamples = 16;

std::unique_ptr<Scene> sceneWithLights(int count, const char* sampling, int samplesPerPixel = kSamples) {
    SceneBuilder builder;
    CameraSettings camera;
    camera.from = Vec3(0, 2, 6);
    camera.to = Vec3(0, 0.6, 0);
    builder.setCamera(camera);
    FilmSettings film;
    film.width = kWidth;
    film.height = kHeight;
    film.samplesPerPixel = samplesPerPixel;
    builder.setFilm(film);
    builder.setIntegrator(geometry::Json{{"type", "path"}, {"max_depth", 4}, {"light_sampler", sampling}});
    SceneObject ball;
    ball.kind = SceneObject::Kind::Implicit;
    ball.material = builder.addMaterial("grey", {{"type", "diffuse"}, {"albedo", {0.7, 0.7, 0.7}}});
    const geometry::FieldLibrary none(geometry::Json::object(), "/fields", "bench");
    ball.shape = builder.addSurface(std::make_unique<geometry::ImplicitSurface>(
        none.compileDescription(geometry::Json{{"type", "sphere"}, {"radius", 0.8}}, "")));
    ball.worldFromObject(1, 3) = 0.8;
    builder.addObject(ball);
    SceneObject floor;
    floor.material = builder.addMaterial("floor", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}});
    TriangleMesh mesh;
    mesh.positions = {-20, 0, -20, 20, 0, -20, 20, 0, 20, -20, 0, 20};
    mesh.indices = {0, 2, 1, 0, 3, 2};
    floor.shape = builder.addMesh(std::move(mesh));
    builder.addObject(floor);
    // A grid of quads 3 m up over a 6 m square, facing down, each 0.6 of
    // its cell wide, of the same total power whatever their number.
    const int side = int(std::ceil(std::sqrt(double(count))));
    const double cell = 6.0 / side, size = 0.6 * cell;
    const double radiance = 200.0 * 0.04 / (count * size * size);
    for (int i = 0; i < count; ++i) {
        const double x = -3 + cell * (i % side + 0.5), z = -3 + cell * (i / side + 0.5);
        builder.addLight({{"type", "quad"}, {"corner", {x - size / 2, 3, z - size / 2}}, {"edge1", {size, 0, 0}},
                          {"edge2", {0, 0, size}}, {"radiance", {radiance, radiance, radiance}}});
    }
    return builder.build();
}


double squaredError(const Image& image, const Image& reference) {
    double sum = 0.0;
    for (size_t i = 0; i < image.rgb.size(); ++i) sum += std::pow(double(image.rgb[i]) - reference.rgb[i], 2);
    return sum / double(image.rgb.size());
}

}  // namespace

int main() {
    std::printf("path tracing %dx%d at %d spp, 2 threads, median of 3 runs\n", kWidth, kHeight, kSamples);
    std::printf("| lights | tree | tree / one light | exhaustive | exhaustive / one light |\n| --- | --- | --- | --- | --- |\n");
    const double pixelSamples = double(kWidth) * kHeight * kSamples;
    double first[2] = {0.0, 0.0};
    for (int count : {1, 10, 100, 1000, 10000}) {
        double perSample[2] = {0.0, 0.0};
        for (int k = 0; k < 2; ++k) {
            // The exhaustive walk at 10^4 lights takes minutes a run: once.
            const auto scene = sceneWithLights(count, k == 0 ? "tree" : "exhaustive");
            const int runs = k == 1 && count >= 10000 ? 1 : 3;
            perSample[k] = bench::medianSeconds(runs, [&] { render(*scene, {.threads = 2, .seed = 1, .quiet = true}); }) /
                           pixelSamples;
            if (count == 1) first[k] = perSample[k];
        }
        std::printf("| %d | %.3f us | %.2fx | %.3f us | %.2fx |\n", count, perSample[0] * 1e6, perSample[0] / first[0],
                    perSample[1] * 1e6, perSample[1] / first[1]);
        std::fflush(stdout);
    }

    // Efficiency at 1,000 lights: the same 16-spp frame by each sampler
    // against a 512-spp reference (by the tree; its own noise adds the same
    // small error to both).
    const Image reference = render(*sceneWithLights(1000, "tree", 512), {.threads = 2, .seed = 99, .quiet = true});
    double mean = 0.0;
    for (const float v : reference.rgb) mean += v;
    std::printf("reference mean %.4f\n", mean / double(reference.rgb.size()));
    std::printf("\n1,000 lights, 16 spp against a 512-spp reference (median of 3 seeds)\n");
    std::printf("| sampler | time | RMSE | efficiency 1/(RMSE^2 t) |\n| --- | --- | --- | --- |\n");
    double efficiency[2] = {0.0, 0.0};
    for (int k = 0; k < 2; ++k) {
        const auto scene = sceneWithLights(1000, k == 0 ? "tree" : "exhaustive");
        std::vector<double> times, errors;
        for (uint64_t seed = 1; seed <= 3; ++seed) {
            const auto start = std::chrono::steady_clock::now();
            const Image image = render(*scene, {.threads = 2, .seed = seed, .quiet = true});
            times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
            errors.push_back(squaredError(image, reference));
        }
        const double t = bench::median(times), e = bench::median(errors);
        efficiency[k] = 1.0 / (e * t);
        std::printf("| %s | %.2f s | %.4f | %.3g |\n", k == 0 ? "tree" : "exhaustive", t, std::sqrt(e), efficiency[k]);
    }
    std::printf("tree / exhaustive efficiency: %.2fx\n", efficiency[0] / efficiency[1]);
}
