// Writing oriented point sets (particles): binary PLY with x y z nx ny nz
// radius, or text .xyz with x y z nx ny nz per line (what variational
// fields read as "points"). Files appear only when complete.
#pragma once

#include <string>
#include <vector>

#include "geometry/particles/surface_particles.h"

namespace isotrace {

/// True for the extensions writePoints knows (.ply, .xyz).
bool isPointSetExtension(const std::string& path);
/// Throws std::runtime_error naming the path when it cannot be written.
void writePoints(const std::string& path, const std::vector<geometry::SurfaceParticle>& points);

}  // namespace isotrace
