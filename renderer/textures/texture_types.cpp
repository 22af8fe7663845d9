// Every texture type a scene file can name. Adding a type: its file in this
// folder, and one line here.
#include "renderer/texture.h"

namespace isotrace {

std::shared_ptr<const Texture> readCheckerTexture(geometry::JsonObjectReader& r, const MaterialContext& context);
std::shared_ptr<const Texture> readNoiseTexture(geometry::JsonObjectReader& r, const MaterialContext& context);
std::shared_ptr<const Texture> readImageTexture(geometry::JsonObjectReader& r, const MaterialContext& context);
std::shared_ptr<const Texture> readFieldRampTexture(geometry::JsonObjectReader& r, const MaterialContext& context);

const Registry<TextureFactory>& textureRegistry() {
    static const Registry<TextureFactory> registry({
        {"checker", readCheckerTexture},
        {"noise", readNoiseTexture},
        {"image", readImageTexture},
        {"field_ramp", readFieldRampTexture},
    });
    return registry;
}

}  // namespace isotrace
