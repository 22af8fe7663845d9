// "environment": constant radiance from every direction, sampled uniformly
// over the sphere. At most one per scene.
#include <cmath>
#include <limits>
#include <numbers>

#include "renderer/light.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class EnvironmentLight final : public Light {
public:
    explicit EnvironmentLight(const RGB& radiance) : radiance_(radiance) {}

    bool isInfinite() const override { return true; }
    LightSample sample(const Vec3&, const Eigen::Vector2d& u) const override {
        LightSample s;
        const double z = 1.0 - 2.0 * u.x();
        const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = 2.0 * std::numbers::pi * u.y();
        s.direction = Vec3(r * std::cos(phi), z, r * std::sin(phi));
        s.distance = std::numeric_limits<double>::infinity();
        s.radiance = radiance_;
        s.pdf = 1.0 / (4.0 * std::numbers::pi);
        return s;
    }
    double pdf(const Vec3&, const Vec3&, const Vec3&) const override { return 1.0 / (4.0 * std::numbers::pi); }
    RGB escapedRadiance(const Vec3&) const override { return radiance_; }
    RGB meanRadiance() const override { return radiance_; }

private:
    RGB radiance_;
};

}  // namespace

void readEnvironmentLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t) {
    if (builder.hasEnvironment()) r.failHere("only one environment light is allowed");
    builder.setEnvironment(std::make_unique<EnvironmentLight>(readColor(r, "radiance", RGB::Ones())));
}

}  // namespace isotrace
