#include "renderer/scene_values.h"

#include <cmath>

#include "geometry/description/transform_description.h"

namespace isotrace {

using geometry::InputError;
using geometry::Json;
using geometry::JsonObjectReader;
using geometry::jsonPointerAppend;
using geometry::Mat4;

RGB readColor(JsonObjectReader& r, const std::string& key, const RGB& fallback, bool nonNegative) {
    if (!r.has(key)) return fallback;
    const geometry::Vec3 v = r.vec3(key);
    if (nonNegative && (v.array() < 0).any()) r.fail(key, "colour components must not be negative");
    // Radiance is summed in single precision: far below its 3.4e38 limit.
    if (!(v.cwiseAbs().maxCoeff() <= 1e30)) r.fail(key, "colour components above 1e30 overflow single-precision sums");
    return v.array();
}

Mat4 readTransform(JsonObjectReader& r) {
    Mat4 m = Mat4::Identity();
    if (r.has("matrix")) {
        const Json& j = r.value("matrix");
        const std::string pointer = r.pointerOf("matrix");
        if (!j.is_array() || j.size() != 4) throw InputError(r.file(), pointer, "expected 4 rows of 4 numbers");
        for (int row = 0; row < 4; ++row) {
            const std::string rp = jsonPointerAppend(pointer, row);
            if (!j[row].is_array() || j[row].size() != 4) throw InputError(r.file(), rp, "expected a row of 4 numbers");
            for (int col = 0; col < 4; ++col)
                m(row, col) = JsonObjectReader::asNumber(j[row][col], jsonPointerAppend(rp, col), r.file());
        }
        if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) r.fail("matrix", "the last row must be [0, 0, 0, 1] (affine)");
        for (const char* key : {"translate", "rotate", "scale"})
            if (r.has(key)) r.fail(key, "give either \"matrix\" or translate/rotate/scale, not both");
    } else {
        const geometry::AffineDescription affine = geometry::readScaleRotateTranslate(r);
        m.topLeftCorner<3, 3>() = affine.linear;
        m.topRightCorner<3, 1>() = affine.translation;
    }
    const double det = m.topLeftCorner<3, 3>().determinant();
    if (!(std::abs(det) > 1e-12) || !std::isfinite(det)) r.failHere("transform is singular (determinant " + std::to_string(det) + ")");
    r.finish();
    return m;
}

}  // namespace isotrace
