// The lights that a scene's objects make, which the scene builder adds
// itself rather than reading them from "lights": an area light for each
// emissive mesh, an emitter for each emissive implicit surface, and the
// images of lights in flat mirrors. They are defined in lights/, with the
// other light types; the builder sees only these factories.
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "renderer/light.h"
#include "renderer/material.h"

namespace isotrace {

class Scene;
struct SceneObject;

/// World-space emissive triangles (lights/area_light.h).
std::unique_ptr<Light> makeAreaLight(std::vector<std::array<Vec3, 3>> triangles, const Emission& emission);

/// An implicit object of a committed scene whose material emits
/// (lights/implicit_emitter_light.h); `scene` must outlive the light.
std::unique_ptr<Light> makeImplicitEmitterLight(const Scene& scene, const SceneObject& object,
                                                const Emission& emission);

/// Finds the scene's plane mirrors and adds the images of its lights in
/// them (not of the environment, which BSDF samples find well, nor of
/// lights across a mirror's plane). Images are skipped, with a warning,
/// past `maxImages` in all. Call once the scene's lights all exist
/// (lights/mirror_image_light.h).
void addMirrorImages(Scene& scene, size_t maxImages = 1024);

}  // namespace isotrace
