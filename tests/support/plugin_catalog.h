// One description of every material and light type, for property tests that
// must hold for all of them; a test fails when a registered type has none.
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
    };
}

inline std::vector<PluginEntry> lightCatalog() {
    return {
        {"point", {{"type", "point"}, {"position", {0.3, 2, -0.2}}, {"intensity", {10, 10, 10}}}},
        {"directional", {{"type", "directional"}, {"direction", {0.2, -1, 0.1}}, {"irradiance", {2, 2, 2}}}},
        {"quad", {{"type", "quad"}, {"corner", {-0.5, 2, -0.5}}, {"edge1", {1, 0, 0}}, {"edge2", {0, 0, 1}}}},
        {"disk", {{"type", "disk"}, {"center", {0, 2, 0}}, {"normal", {0, -1, 0}}, {"radius", 0.5}}},
        {"environment", {{"type", "environment"}, {"radiance", {0.5, 0.6, 0.7}}}},
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
