// Surface materials: Lambertian diffuse, perfect mirror, and emitters.
#pragma once

#include <string>

#include "color.h"

namespace isotrace {

struct Material {
    enum class Type { Diffuse, Mirror, Emissive };
    Type type = Type::Diffuse;
    std::string name;
    RGB albedo = RGB::Constant(0.8);       ///< diffuse reflectance
    RGB reflectance = RGB::Constant(1.0);  ///< mirror reflectance
    RGB radiance = RGB::Zero();            ///< emitted radiance (emissive)
    bool twoSided = false;                 ///< emissive: emit from both faces

    bool isEmissive() const { return type == Type::Emissive; }
};

}  // namespace isotrace
