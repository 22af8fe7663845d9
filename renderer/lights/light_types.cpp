// Every light type a scene file can name, in the order error messages list
// them. Adding a type: its file in this folder, and one line here.
#include "renderer/light.h"

namespace isotrace {

void readPointLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);
void readSpotLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);
void readDirectionalLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);
void readQuadLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);
void readDiskLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);
void readEnvironmentLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t index);

const Registry<LightFactory>& lightRegistry() {
    static const Registry<LightFactory> registry({
        {"point", readPointLight},
        {"spot", readSpotLight},
        {"directional", readDirectionalLight},
        {"quad", readQuadLight},
        {"disk", readDiskLight},
        {"environment", readEnvironmentLight},
    });
    return registry;
}

}  // namespace isotrace
