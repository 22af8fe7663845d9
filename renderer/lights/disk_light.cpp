// "disk": a round emitter, center + normal + radius, as a fan of triangles
// that both the renders and the light's sampling use.
#include <cmath>
#include <numbers>

#include "renderer/light.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {
constexpr int kDiskSegments = 64;
}

void readDiskLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index) {
    Emission emission;
    emission.radiance = readColor(r, "radiance", RGB::Ones());
    emission.twoSided = r.boolean("two_sided", false);
    const Vec3 center = r.vec3("center"), normal = r.vec3("normal", Vec3(0, -1, 0));
    const double radius = r.positiveNumber("radius");
    if (!(normal.norm() > 0)) r.fail("normal", "must not be the zero vector");
    const Vec3 n = normal.normalized();
    const Vec3 a = (std::abs(n.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0)).cross(n).normalized();
    const Vec3 b = n.cross(a);
    TriangleMesh mesh;
    mesh.positions.insert(mesh.positions.end(), {float(center.x()), float(center.y()), float(center.z())});
    for (int k = 0; k < kDiskSegments; ++k) {
        const double phi = 2.0 * std::numbers::pi * k / kDiskSegments;
        const Vec3 p = center + radius * (std::cos(phi) * a + std::sin(phi) * b);
        mesh.positions.insert(mesh.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
        mesh.indices.insert(mesh.indices.end(), {0u, uint32_t(1 + k), uint32_t(1 + (k + 1) % kDiskSegments)});
    }
    builder.addEmitter(std::move(mesh), emission, "light " + std::to_string(index));
}

}  // namespace isotrace
