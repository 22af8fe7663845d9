// Every material type a scene file can name, in the order error messages
// list them. Adding a type: its file in this folder, and one line here.
#include "renderer/material.h"

namespace isotrace {

Material readDiffuseMaterial(geometry::JsonObjectReader& r);
Material readMirrorMaterial(geometry::JsonObjectReader& r);
Material readEmissiveMaterial(geometry::JsonObjectReader& r);

const Registry<MaterialFactory>& materialRegistry() {
    static const Registry<MaterialFactory> registry({
        {"diffuse", readDiffuseMaterial},
        {"mirror", readMirrorMaterial},
        {"emissive", readEmissiveMaterial},
    });
    return registry;
}

}  // namespace isotrace
