// "spot": a point light limited to a cone, as Blender 3.4 defines it: the
// full cone angle (Blender's spot size) and a blend in [0, 1] that softens
// the edge over that fraction of 1 - cos(half angle). Inside the cone the
// intensity is I cos(theta), theta from the axis, times smoothstep across
// the blend (Cycles 3.4's spot_light_attenuation), so that a Blender spot
// and its isotrace export light a scene alike.
#include <cmath>
#include <numbers>

#include "renderer/light.h"
#include "renderer/lights/point_emitter.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class SpotLight final : public Light {
public:
    SpotLight(const Vec3& position, const Vec3& axis, const RGB& intensity, double coneAngleRadians, double blend)
        : position_(position),
          axis_(axis.normalized()),
          intensity_(intensity),
          cosHalfAngle_(std::cos(0.5 * coneAngleRadians)),
          smoothWidth_((1.0 - cosHalfAngle_) * blend) {}

    /// The intensity's factor towards unit direction `w` (from the light).
    double falloff(const Vec3& w) const {
        const double cosTheta = w.dot(axis_);
        if (cosTheta <= cosHalfAngle_) return 0.0;
        const double t = cosTheta - cosHalfAngle_;
        if (smoothWidth_ > 0.0 && t < smoothWidth_) {
            const double x = t / smoothWidth_;
            return cosTheta * x * x * (3.0 - 2.0 * x);
        }
        return cosTheta;
    }

    bool isDelta() const override { return true; }
    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d&) const override {
        LightSample s = pointEmitterSample(position_, intensity_, context);
        s.radiance *= falloff(-s.direction);
        return s;
    }
    int sideOfPlane(const Vec3& point, const Vec3& normal) const override {
        return sideOfPlaneOfPoint(position_, point, normal);
    }
    double importance(const LightSampleContext& context) const override {
        const Vec3 d = position_ - context.p;
        const double d2 = d.squaredNorm(), distance = std::sqrt(d2);
        const double cosReceiver = context.n.isZero() ? 1.0 : context.n.dot(d) / distance;
        if (!(cosReceiver > 0)) return 0.0;
        return luminance(intensity_) * falloff(-d / distance) * cosReceiver / d2;
    }
    std::optional<LightBounds> bounds() const override {
        LightBounds b = pointSourceBounds(position_, luminance(intensity_));
        b.axis = axis_;
        b.cosNormalSpread = 1.0;
        b.cosEmissionSpread = cosHalfAngle_;
        return b;
    }

private:
    Vec3 position_;
    Vec3 axis_;
    RGB intensity_;
    double cosHalfAngle_;
    double smoothWidth_;
};

}  // namespace

void readSpotLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t) {
    const Vec3 position = r.vec3("position");
    const Vec3 direction = r.vec3("direction");
    if (!(direction.norm() > 0)) r.fail("direction", "must not be the zero vector");
    const double coneAngle = r.number("cone_angle", 45.0);
    if (!(coneAngle > 0 && coneAngle <= 180)) r.fail("cone_angle", "must be in (0, 180] degrees");
    const double blend = r.number("blend", 0.15);
    if (!(blend >= 0 && blend <= 1)) r.fail("blend", "must be between 0 and 1");
    builder.addLight(std::make_unique<SpotLight>(position, direction, readColor(r, "intensity", RGB::Ones()),
                                                 coneAngle * std::numbers::pi / 180.0, blend));
}

}  // namespace isotrace
