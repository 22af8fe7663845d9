// Warping uniform samples to directions, and the weights that combine
// sampling strategies.
#pragma once

#include <Eigen/Core>

#include "geometry/vector_types.h"

namespace isotrace {

using geometry::Vec3;

/// Unit vectors s, t completing unit n to a right-handed orthonormal basis,
/// without branches on n's direction (Duff et al. 2017).
void orthonormalBasis(const Vec3& n, Vec3& s, Vec3& t);
/// An orthonormal frame around a normal: local coordinates have the normal
/// as z, as microfacet formulas want.
struct Frame {
    Vec3 s, t, n;
    explicit Frame(const Vec3& normal) : n(normal) { orthonormalBasis(n, s, t); }
    Vec3 toLocal(const Vec3& v) const { return {v.dot(s), v.dot(t), v.dot(n)}; }
    Vec3 toWorld(const Vec3& v) const { return v.x() * s + v.y() * t + v.z() * n; }
};
/// A uniform direction on the unit sphere (density 1 / (4 pi)).
Vec3 sampleUniformSphere(const Eigen::Vector2d& u);
/// Cosine-weighted direction around unit normal n (density cos / pi).
Vec3 sampleCosineHemisphere(const Vec3& n, const Eigen::Vector2d& u);
/// A point of [0, 1] with density proportional to (1 - x) a + x b
/// (a, b >= 0, not both 0), by inverting its distribution.
double sampleLinear(double u, double a, double b);
/// A point of [0, 1]^2 with density proportional to the bilinear function
/// with corner values a00 (0, 0), a10 (1, 0), a01 (0, 1), a11 (1, 1):
/// the second coordinate from its marginal, then the first given it.
Eigen::Vector2d sampleBilinear(const Eigen::Vector2d& u, double a00, double a10, double a01, double a11);
/// The bilinear function's value at p over its mean: sampleBilinear's density.
double bilinearPdf(const Eigen::Vector2d& p, double a00, double a10, double a01, double a11);
/// Multiple importance sampling: Veach's power heuristic with exponent 2.
inline double powerHeuristic(double a, double b) { return a * a / (a * a + b * b); }
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - 2.0 * d.dot(n) * n; }

}  // namespace isotrace
