// Materials: a BSDF for the light a surface scatters, an emission for the
// light it gives off, or both. The scene file's materials are read by the
// factories of material_registry(), one file per type in materials/.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "renderer/bsdf.h"
#include "renderer/registry.h"
#include "renderer/texture.h"

namespace isotrace {

/// Light a surface gives off: uniform radiance from its front face (the
/// side its normal points to), or from both.
struct Emission {
    RGB radiance = RGB::Zero();
    bool twoSided = false;
    /// Radiance leaving a point with normal n towards direction w.
    RGB emitted(const Vec3& n, const Vec3& w) const {
        return (twoSided || n.dot(w) > 0) ? radiance : RGB::Zero();
    }
};

struct Material {
    std::string name;
    /// Null for pure emitters, which reflect nothing.
    std::shared_ptr<const BSDF> bsdf;
    std::optional<Emission> emission;

    bool isEmissive() const { return emission.has_value(); }
    /// What albedo AOVs show: the BSDF's albedo, else the emitted radiance.
    RGB albedo(const ShadingPoint& p) const {
        return bsdf ? bsdf->albedo(p) : emission ? emission->radiance : RGB::Zero();
    }
};

/// Reads one material's keys (the reader is left for the caller to finish).
using MaterialFactory = Material (*)(geometry::JsonObjectReader& r, const MaterialContext& context);
const Registry<MaterialFactory>& materialRegistry();

}  // namespace isotrace
