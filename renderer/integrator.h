// Light transport: the radiance arriving along a camera ray.
#pragma once

#include <memory>

#include "color.h"
#include "sampler.h"
#include "scene.h"

namespace isotrace {

class Integrator {
public:
    explicit Integrator(const Scene& scene) : scene_(scene) {}
    virtual ~Integrator() = default;
    virtual RGB radiance(const Ray& ray, Sampler& sampler) const = 0;

protected:
    const Scene& scene_;
};

/// Unidirectional path tracing with next-event estimation, multiple
/// importance sampling (power heuristic) and Russian roulette.
std::unique_ptr<Integrator> makePathIntegrator(const Scene& scene);
/// Direct light with hard shadows and mirror recursion: the fast preview.
std::unique_ptr<Integrator> makeWhittedIntegrator(const Scene& scene);
std::unique_ptr<Integrator> makeIntegrator(const Scene& scene);

// Shared helpers.

/// Distance to push a ray's origin off a surface at p (relative to p's
/// magnitude, so float positions in Embree do not re-hit the surface).
inline double rayOffset(const Vec3& p) { return 1e-4 * (1.0 + p.cwiseAbs().maxCoeff()); }
/// Origin for a ray leaving a surface at p (geometric normal n) towards w.
inline Vec3 offsetOrigin(const Vec3& p, const Vec3& n, const Vec3& w) {
    return p + (n.dot(w) >= 0 ? 1.0 : -1.0) * rayOffset(p) * n;
}
/// Cosine-weighted direction around unit normal n.
Vec3 sampleCosineHemisphere(const Vec3& n, const Eigen::Vector2d& u);
inline Vec3 reflect(const Vec3& d, const Vec3& n) { return d - 2.0 * d.dot(n) * n; }
inline double powerHeuristic(double a, double b) { return a * a / (a * a + b * b); }

}  // namespace isotrace
