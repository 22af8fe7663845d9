// A diffuse floor (albedo 0.5, 120 m wide) at height y with whatever a test
// adds (lights, emitters), and the floor's radiance seen straight down: the
// setting of the closed-form light tests.
#pragma once

#include <functional>
#include <memory>

#include "renderer/scene_builder.h"

namespace isotrace::testing {

inline std::unique_ptr<Scene> floorScene(const geometry::Json& integrator, double y,
                                         const std::function<void(SceneBuilder&)>& add) {
    SceneBuilder builder;
    builder.setIntegrator(integrator);
    SceneObject floor;
    floor.material = builder.addMaterial("floor grey", {{"type", "diffuse"}, {"albedo", {0.5, 0.5, 0.5}}});
    TriangleMesh mesh;
    const float h = float(y);
    mesh.positions = {-60, h, -60, 60, h, -60, 60, h, 60, -60, h, 60};
    mesh.indices = {0, 2, 1, 0, 3, 2};
    floor.shape = builder.addMesh(std::move(mesh));
    builder.addObject(floor);
    add(builder);
    return builder.build();
}

/// The same with integrator type `integrator` at depth 1.
inline std::unique_ptr<Scene> floorScene(const char* integrator, double y, const std::function<void(SceneBuilder&)>& add) {
    return floorScene(geometry::Json{{"type", integrator}, {"max_depth", 1}}, y, add);
}

/// The mean green radiance of `samples` paths looking straight down from
/// `from` (stratified Sobol samples, seeded by `seed`).
inline double radianceLookingDown(const Scene& scene, const Vec3& from, int samples, uint64_t seed) {
    Sampler sampler(SamplerType::Sobol, seed);
    double sum = 0.0;
    for (int s = 0; s < samples; ++s) {
        sampler.startPixelSample(0, 0, s);
        sum += scene.integrator->radiance(scene, Ray{from, Vec3(0, -1, 0)}, sampler)[1];
    }
    return sum / samples;
}

}  // namespace isotrace::testing
