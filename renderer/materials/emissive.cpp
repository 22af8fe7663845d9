// "emissive": an area light's surface. It emits and reflects nothing; a
// mesh with it is sampled as a light.
#include "renderer/material.h"
#include "renderer/scene_values.h"

namespace isotrace {

Material readEmissiveMaterial(geometry::JsonObjectReader& r, const MaterialContext&) {
    Material m;
    Emission e;
    e.radiance = readColor(r, "radiance", RGB::Ones());
    e.twoSided = r.boolean("two_sided", false);
    m.emission = e;
    return m;
}

}  // namespace isotrace
