// "checker": a solid 3D checkerboard in object space, cubes of side
// `scale` alternating between two values, so any surface cut through it
// shows the pattern without UVs.
#include <cmath>

#include "renderer/textures/two_colors.h"

namespace isotrace {

namespace {

class CheckerTexture final : public Texture {
public:
    CheckerTexture(const TwoColors& colors, double scale) : colors_(colors), inverseScale_(1.0 / scale) {}

    RGB evaluate(const ShadingPoint& p) const override {
        const Vec3 q = p.objectPosition * inverseScale_;
        const long long sum = static_cast<long long>(std::floor(q.x())) + static_cast<long long>(std::floor(q.y())) +
                              static_cast<long long>(std::floor(q.z()));
        return (sum & 1) ? colors_.b : colors_.a;
    }
    int channels() const override { return colors_.channels; }
    RGB minimum() const override { return colors_.a.min(colors_.b); }
    RGB maximum() const override { return colors_.a.max(colors_.b); }

private:
    TwoColors colors_;
    double inverseScale_;
};

}  // namespace

std::shared_ptr<const Texture> readCheckerTexture(geometry::JsonObjectReader& r, const MaterialContext&) {
    const double scale = r.positiveNumber("scale", 1.0);
    return std::make_shared<CheckerTexture>(TwoColors::read(r), scale);
}

}  // namespace isotrace
