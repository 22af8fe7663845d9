// Every material type a scene file can name, in the order error messages
// list them. Adding a type: its file in this folder, and one line here.
#include "renderer/material.h"

namespace isotrace {

Material readDiffuseMaterial(geometry::JsonObjectReader& r, const MaterialContext& context);
Material readMirrorMaterial(geometry::JsonObjectReader& r, const MaterialContext& context);
Material readEmissiveMaterial(geometry::JsonObjectReader& r, const MaterialContext& context);
Material readConductorMaterial(geometry::JsonObjectReader& r, const MaterialContext& context);
Material readDielectricMaterial(geometry::JsonObjectReader& r, const MaterialContext& context);
Material readPlasticMaterial(geometry::JsonObjectReader& r, const MaterialContext& context);

const Registry<MaterialFactory>& materialRegistry() {
    static const Registry<MaterialFactory> registry({
        {"diffuse", readDiffuseMaterial},
        {"mirror", readMirrorMaterial},
        {"emissive", readEmissiveMaterial},
        {"conductor", readConductorMaterial},
        {"dielectric", readDielectricMaterial},
        {"plastic", readPlasticMaterial},
    });
    return registry;
}

}  // namespace isotrace
