// "environment": radiance from every direction around the scene. At most
// one per scene.
#include <cmath>
#include <limits>
#include <numbers>

#include "renderer/light.h"
#include "renderer/scene_builder.h"
#include "renderer/sampling.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class EnvironmentLight final : public Light {
public:
    explicit EnvironmentLight(const RGB& radiance) : radiance_(radiance) {}

    bool isInfinite() const override { return true; }
    /// From a surface: cosine-weighted over the hemisphere it sees, the
    /// density that makes a constant environment's estimate exact for a
    /// Lambertian surface. From a point in space: uniform over the sphere.
    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const override {
        LightSample s;
        if (context.n.isZero()) {
            const double z = 1.0 - 2.0 * u.x();
            const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
            const double phi = 2.0 * std::numbers::pi * u.y();
            s.direction = Vec3(r * std::cos(phi), z, r * std::sin(phi));
        } else {
            s.direction = sampleCosineHemisphere(context.n, u);
        }
        s.distance = std::numeric_limits<double>::infinity();
        s.radiance = radiance_;
        s.pdf = pdf(context, s.direction, {}, {});
        return s;
    }
    double pdf(const LightSampleContext& context, const Vec3& wi, const Vec3&, const Vec3&) const override {
        if (context.n.isZero()) return 1.0 / (4.0 * std::numbers::pi);
        const double cosTheta = context.n.dot(wi);
        return cosTheta > 0 ? cosTheta / std::numbers::pi : 0.0;
    }
    RGB escapedRadiance(const Vec3&) const override { return radiance_; }
    RGB meanRadiance() const override { return radiance_; }
    /// Irradiance pi L on a surface (4 pi L of fluence at a point in space).
    double importance(const LightSampleContext& context) const override {
        return luminance(radiance_) * (context.n.isZero() ? 4.0 : 1.0) * std::numbers::pi;
    }

private:
    RGB radiance_;
};

}  // namespace

void readEnvironmentLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t) {
    if (builder.hasEnvironment()) r.failHere("only one environment light is allowed");
    builder.setEnvironment(std::make_unique<EnvironmentLight>(readColor(r, "radiance", RGB::Ones())));
}

}  // namespace isotrace
