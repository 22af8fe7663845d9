// "point": an isotropic point light of the given intensity (W/sr).
#include <cmath>

#include "renderer/light.h"
#include "renderer/lights/point_emitter.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class PointLight final : public Light {
public:
    PointLight(const Vec3& position, const RGB& intensity) : position_(position), intensity_(intensity) {}

    bool isDelta() const override { return true; }
    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d&) const override {
        return pointEmitterSample(position_, intensity_, context);
    }
    int sideOfPlane(const Vec3& point, const Vec3& normal) const override {
        return sideOfPlaneOfPoint(position_, point, normal);
    }
    double importance(const LightSampleContext& context) const override {
        const Vec3 d = position_ - context.p;
        const double d2 = d.squaredNorm();
        const double cosReceiver = context.n.isZero() ? 1.0 : context.n.dot(d) / std::sqrt(d2);
        return cosReceiver > 0 ? luminance(intensity_) * cosReceiver / d2 : 0.0;
    }
    std::optional<LightBounds> bounds() const override { return pointSourceBounds(position_, luminance(intensity_)); }

private:
    Vec3 position_;
    RGB intensity_;
};

}  // namespace

void readPointLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t) {
    const Vec3 position = r.vec3("position");
    builder.addLight(std::make_unique<PointLight>(position, readColor(r, "intensity", RGB::Ones())));
}

}  // namespace isotrace
