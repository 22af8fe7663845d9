// Spheres from a PLY file (ASCII or binary little-endian): the first
// element must be "vertex" with properties x, y, z and optionally radius,
// of any scalar type; other properties and elements are ignored. A
// scatter's operand list (fields/sphere_set.h) for millions of spheres,
// read without parsing JSON.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/fields/sphere.h"

namespace isotrace::geometry {

/// The spheres of `path`; rows without a radius column take
/// `defaultRadius`. Throws InputError naming the file and the line or
/// vertex for a missing or unreadable file, a header without x, y and z
/// (or without radius when no default is given), list properties in the
/// vertex element, a vertex count past `maxSpheres`, data that ends early,
/// and coordinates or radii that are not finite or radii that are not
/// positive.
std::vector<SphereField> readSphereFile(const std::string& path, std::optional<double> defaultRadius,
                                        double maxSpheres);

}  // namespace isotrace::geometry
