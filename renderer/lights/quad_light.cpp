// "quad": a parallelogram that emits: emissive geometry (visible, and
// sampled as an area light), corner + edge1 + edge2.
#include "renderer/light.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_values.h"

namespace isotrace {

void readQuadLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index) {
    Emission emission;
    emission.radiance = readColor(r, "radiance", RGB::Ones());
    emission.twoSided = r.boolean("two_sided", false);
    const Vec3 corner = r.vec3("corner"), e1 = r.vec3("edge1"), e2 = r.vec3("edge2");
    if (!(e1.cross(e2).norm() > 0)) r.fail("edge2", "the quad's edges must not be parallel or zero");
    TriangleMesh mesh;
    for (const Vec3& p : {corner, Vec3(corner + e1), Vec3(corner + e1 + e2), Vec3(corner + e2)})
        mesh.positions.insert(mesh.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
    mesh.indices = {0, 1, 2, 0, 2, 3};
    builder.addEmitter(std::move(mesh), emission, "light " + std::to_string(index));
}

}  // namespace isotrace
