#include "geometry/description/transform_description.h"

#include <numbers>

namespace isotrace::geometry {

AffineDescription readScaleRotateTranslate(JsonObjectReader& r) {
    Mat3 scale = Mat3::Identity();
    if (const Json* s = r.optionalValue("scale")) {
        if (s->is_number()) {
            const double v = JsonObjectReader::asNumber(*s, r.pointerOf("scale"), r.file());
            if (!(v > 0)) r.fail("scale", "must be greater than 0");
            scale = v * Mat3::Identity();
        } else {
            const Vec3 v = JsonObjectReader::asVec3(*s, r.pointerOf("scale"), r.file());
            if ((v.array() <= 0).any()) r.fail("scale", "every factor must be greater than 0");
            scale = v.asDiagonal();
        }
    }
    Mat3 rotation = Mat3::Identity();
    if (r.has("rotate")) {
        JsonObjectReader rot = r.object("rotate");
        const Vec3 axis = rot.vec3("axis");
        const double degrees = rot.number("angle");
        rot.finish();
        if (!(axis.norm() > 0)) rot.fail("axis", "must not be the zero vector");
        rotation = Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()).toRotationMatrix();
    }
    return {rotation * scale, r.vec3("translate", Vec3::Zero())};
}

}  // namespace isotrace::geometry
