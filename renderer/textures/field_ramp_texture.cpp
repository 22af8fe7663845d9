// "field_ramp": colour by a field of the scene, evaluated at the shading
// point in object space, through a ramp: the field's value (distance to a
// skeleton, the strength of one blob) or the mean curvature of its level
// set there (from the field's gradient and its finite-differenced
// Hessian). It shades a blend by where it came from, on the implicit
// surface and on its mesh alike.
#include <cmath>

#include "geometry/description/field_parser.h"
#include "renderer/texture.h"

namespace isotrace {

namespace {

enum class FieldQuantity { Value, MeanCurvature };

class FieldRampTexture final : public Texture {
public:
    FieldRampTexture(geometry::FieldProgram field, FieldQuantity quantity, ValueRamp ramp)
        : field_(std::move(field)), quantity_(quantity), ramp_(std::move(ramp)) {}

    RGB evaluate(const ShadingPoint& p) const override {
        const Vec3& x = p.objectPosition;
        return ramp_.at(quantity_ == FieldQuantity::Value ? field_.value(x) : meanCurvature(x));
    }
    int channels() const override { return ramp_.channels(); }
    RGB minimum() const override { return ramp_.minimum(); }
    RGB maximum() const override { return ramp_.maximum(); }

    /// div(grad f / |grad f|) / 2: 1 / r on a sphere of radius r, positive
    /// where the surface is convex.
    double meanCurvature(const Vec3& x) const {
        Vec3 g;
        field_.valueAndGradient(x, g);
        const double h = 1e-4 * (1.0 + x.cwiseAbs().maxCoeff());
        geometry::Mat3 hessian;
        for (int axis = 0; axis < 3; ++axis) {
            Vec3 step = Vec3::Zero();
            step[axis] = h;
            Vec3 gPlus, gMinus;
            field_.valueAndGradient(x + step, gPlus);
            field_.valueAndGradient(x - step, gMinus);
            hessian.col(axis) = (gPlus - gMinus) / (2 * h);
        }
        const double g2 = g.squaredNorm();
        if (!(g2 > 0)) return 0.0;
        return (g2 * hessian.trace() - g.dot(hessian * g)) / (2.0 * g2 * std::sqrt(g2));
    }

private:
    geometry::FieldProgram field_;
    FieldQuantity quantity_;
    ValueRamp ramp_;
};

}  // namespace

std::shared_ptr<const Texture> readFieldRampTexture(geometry::JsonObjectReader& r, const MaterialContext& context) {
    const std::string name = r.string("field");
    if (!context.fields || !context.fields->contains(name)) {
        std::string message = "unknown field \"" + name + "\"";
        if (context.fields)
            if (auto near = geometry::nearestName(name, context.fields->names())) message += " (did you mean \"" + *near + "\"?)";
        r.fail("field", message);
    }
    const std::string quantity = r.choice("quantity", {"value", "mean_curvature"}, "value");
    ValueRamp ramp = ValueRamp::read(r, "ramp");
    return std::make_shared<FieldRampTexture>(context.fields->compile(name),
                                              quantity == "value" ? FieldQuantity::Value : FieldQuantity::MeanCurvature,
                                              std::move(ramp));
}

}  // namespace isotrace
