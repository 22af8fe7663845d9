// One description of every material, light, texture and integrator type, for
// property tests that must hold for all of them; a test fails when a
// registered type has none.
#pragma once

#include <string>
#include <vector>

#include "geometry/description/json_reader.h"

namespace isotrace::testing {

struct PluginEntry {
    std::string name;
    geometry::Json description;
};
inline void PrintTo(const PluginEntry& e, std::ostream* os) { *os << e.name; }

inline std::vector<PluginEntry> materialCatalog() {
    return {
        {"diffuse", {{"type", "diffuse"}, {"albedo", {0.9, 0.5, 0.2}}}},
        {"mirror", {{"type", "mirror"}, {"reflectance", {0.9, 0.8, 0.7}}}},
        {"emissive", {{"type", "emissive"}, {"radiance", {3, 2, 1}}, {"two_sided", true}}},
        {"conductor_gold", {{"type", "conductor"}, {"metal", "gold"}}},
        {"conductor_rough", {{"type", "conductor"}, {"metal", "copper"}, {"roughness", 0.3}}},
        {"conductor_very_rough", {{"type", "conductor"}, {"reflectance", {0.9, 0.6, 0.3}}, {"roughness", 1.0}}},
        {"conductor_single_scattering",
         {{"type", "conductor"}, {"metal", "gold"}, {"roughness", 0.6}, {"multiple_scattering", false}}},
        {"conductor_textured",
         {{"type", "conductor"},
          {"eta", {0.2, 0.4, 1.3}},
          {"k", {3.4, 2.3, 1.8}},
          {"roughness", {{"type", "checker"}, {"scale", 0.1}, {"colors", {0.2, 0.6}}}}}},
        {"dielectric", {{"type", "dielectric"}, {"ior", 1.5}}},
        {"dielectric_rough", {{"type", "dielectric"}, {"ior", 1.5}, {"roughness", 0.3}}},
        {"dielectric_very_rough", {{"type", "dielectric"}, {"ior", 1.33}, {"roughness", 1.0}}},
        {"dielectric_single_scattering",
         {{"type", "dielectric"}, {"ior", 1.5}, {"roughness", 0.6}, {"multiple_scattering", false}}},
        {"dielectric_dense_rough", {{"type", "dielectric"}, {"ior", 2.4}, {"roughness", 0.6}}},
        {"dielectric_thin", {{"type", "dielectric"}, {"ior", 1.5}, {"thin", true}, {"transmittance", {0.9, 0.95, 1}}}},
        {"plastic", {{"type", "plastic"}, {"albedo", {0.8, 0.3, 0.2}}}},
        {"plastic_rough", {{"type", "plastic"}, {"albedo", {0.2, 0.5, 0.9}}, {"roughness", 0.3}}},
        {"plastic_very_rough", {{"type", "plastic"}, {"albedo", {0.9, 0.9, 0.9}}, {"ior", 1.7}, {"roughness", 1.0}}},
        {"plastic_single_scattering",
         {{"type", "plastic"}, {"albedo", {0.5, 0.5, 0.5}}, {"roughness", 0.6}, {"multiple_scattering", false}}},
        {"diffuse_noise", {{"type", "diffuse"}, {"albedo", {{"type", "noise"}, {"scale", 0.3}, {"colors", {{0.1, 0.2, 0.3}, {0.9, 0.8, 0.7}}}}}}},
    };
}

inline std::vector<PluginEntry> lightCatalog() {
    return {
        {"point", {{"type", "point"}, {"position", {0.3, 2, -0.2}}, {"intensity", {10, 10, 10}}}},
        {"spot", {{"type", "spot"}, {"position", {0.3, 2, -0.2}}, {"direction", {0, -1, 0.1}}, {"intensity", {10, 10, 10}},
                  {"cone_angle", 70}, {"blend", 0.3}}},
        {"directional", {{"type", "directional"}, {"direction", {0.2, -1, 0.1}}, {"irradiance", {2, 2, 2}}}},
        {"quad", {{"type", "quad"}, {"corner", {-0.5, 2, -0.5}}, {"edge1", {1, 0, 0}}, {"edge2", {0, 0, 1}}}},
        {"disk", {{"type", "disk"}, {"center", {0, 2, 0}}, {"normal", {0, -1, 0}}, {"radius", 0.5}}},
        {"environment", {{"type", "environment"}, {"radiance", {0.5, 0.6, 0.7}}}},
    };
}

/// Textures; `image` reads "catalog.exr" and `field_ramp` the field "ball",
/// which the texture tests provide.
inline std::vector<PluginEntry> textureCatalog() {
    return {
        {"checker", {{"type", "checker"}, {"scale", 0.4}, {"colors", {{0.1, 0.2, 0.3}, {0.9, 0.8, 0.7}}}}},
        {"noise", {{"type", "noise"}, {"scale", 0.3}, {"colors", {0.2, 0.7}}, {"seed", 3}}},
        {"image", {{"type", "image"}, {"file", "catalog.exr"}, {"scale", 0.5}}},
        {"field_ramp", {{"type", "field_ramp"}, {"field", "ball"}, {"ramp", {{-2, {0, 0, 0}}, {2, {1, 0.5, 0.25}}}}}},
        {"field_ramp_curvature",
         {{"type", "field_ramp"}, {"field", "ball"}, {"quantity", "mean_curvature"}, {"ramp", {{0, 0.1}, {1, 0.9}}}}},
    };
}

inline std::vector<PluginEntry> integratorCatalog() {
    return {
        {"path", {{"type", "path"}, {"max_depth", 5}}},
        {"path_roulette_first", {{"type", "path"}, {"max_depth", 5}, {"rr_depth", 1}}},
        {"whitted", {{"type", "whitted"}}},
    };
}

/// The registered names that `catalog` has no entry for.
inline std::vector<std::string> missingFrom(const std::vector<PluginEntry>& catalog,
                                            const std::vector<std::string>& registered) {
    std::vector<std::string> missing;
    for (const std::string& name : registered) {
        bool found = false;
        for (const PluginEntry& e : catalog) found |= e.description.value("type", "") == name;
        if (!found) missing.push_back(name);
    }
    return missing;
}

}  // namespace isotrace::testing
