// Time per sample with 1, 10 and 300 quad lights over a sphere on a floor
// (the same total power), path traced at 160x90 and 16 spp on 2 threads,
// median of 5 runs: choosing a light walks every light's importance, so
// the cost per sample grows with the count, but slowly.
#include <cmath>
#include <cstdio>

#include "bench_support.h"
#include "geometry/description/field_parser.h"
#include "renderer/render.h"
#include "renderer/scene_builder.h"

using namespace isotrace;

namespace {

std::unique_ptr<Scene> sceneWithLights(int count) {
    SceneBuilder builder;
    CameraSettings camera;
    camera.from = Vec3(0, 2, 6);
    camera.to = Vec3(0, 0.6, 0);
    builder.setCamera(camera);
    FilmSettings film;
    film.width = 160;
    film.height = 90;
    film.samplesPerPixel = 16;
    builder.setFilm(film);
    builder.setIntegrator(geometry::Json{{"type", "path"}, {"max_depth", 4}});
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
    // A grid of small quads 3 m up, sharing 40 W/sr-ish of power.
    const int side = int(std::ceil(std::sqrt(double(count))));
    const double radiance = 200.0 / count;
    for (int i = 0; i < count; ++i) {
        const double x = -3 + 6.0 * (i % side + 0.5) / side, z = -3 + 6.0 * (i / side + 0.5) / side;
        builder.addLight({{"type", "quad"}, {"corner", {x - 0.1, 3, z - 0.1}}, {"edge1", {0, 0, 0.2}},
                          {"edge2", {0.2, 0, 0}}, {"radiance", {radiance, radiance, radiance}}});
    }
    return builder.build();
}

}  // namespace

int main() {
    std::printf("path tracing 160x90 at 16 spp, 2 threads, median of 5 runs\n");
    double first = 0.0;
    for (int count : {1, 10, 300}) {
        const auto scene = sceneWithLights(count);
        const double seconds = bench::medianSeconds(5, [&] { render(*scene, {.threads = 2, .seed = 1, .quiet = true}); });
        const double perSample = seconds / (160.0 * 90 * 16);
        if (count == 1) first = perSample;
        std::printf("%4d lights: %.3f us per sample (%.2fx one light)\n", count, perSample * 1e6, perSample / first);
    }
}
