// "directional": parallel light from infinitely far away; "irradiance" falls
// on a surface facing it.
#include <limits>

#include "renderer/light.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class DirectionalLight final : public Light {
public:
    /// `direction` is the direction light travels.
    DirectionalLight(const Vec3& direction, const RGB& irradiance)
        : direction_(direction.normalized()), irradiance_(irradiance) {}

    bool isDelta() const override { return true; }
    bool isInfinite() const override { return true; }
    LightSample sample(const LightSampleContext&, const Eigen::Vector2d&) const override {
        LightSample s;
        s.direction = -direction_;
        s.distance = std::numeric_limits<double>::infinity();
        s.radiance = irradiance_;
        s.pdf = 1.0;
        s.isDelta = true;
        return s;
    }
    // The light comes from infinitely far on the side it travels away from.
    int sideOfPlane(const Vec3&, const Vec3& normal) const override {
        const double c = -normal.dot(direction_);
        return c > 0 ? 1 : c < 0 ? -1 : 0;
    }
    double importance(const LightSampleContext& context) const override {
        const double cosReceiver = context.n.isZero() ? 1.0 : -context.n.dot(direction_);
        return cosReceiver > 0 ? luminance(irradiance_) * cosReceiver : 0.0;
    }

private:
    Vec3 direction_;
    RGB irradiance_;
};

}  // namespace

void readDirectionalLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t) {
    const Vec3 d = r.vec3("direction");
    if (!(d.norm() > 0)) r.fail("direction", "must not be the zero vector");
    builder.addLight(std::make_unique<DirectionalLight>(d, readColor(r, "irradiance", RGB::Ones())));
}

}  // namespace isotrace
