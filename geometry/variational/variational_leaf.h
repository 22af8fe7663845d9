// A variational implicit surface as a leaf of field programs. The fitted
// field is shared, not copied: every octree cell's pruned program holds one.
#pragma once

#include <memory>

#include "geometry/variational/variational_field.h"

namespace isotrace::geometry {

struct VariationalLeafField {
    std::shared_ptr<const VariationalField> field;

    double value(const Vec3& p) const { return field->value(p); }
    double valueAndGradient(const Vec3& p, Vec3& gradient) const { return field->valueAndGradient(p, gradient); }
    double valueAndSafeDistance(const Vec3& p, double& safe) const { return field->valueAndSafeDistance(p, safe); }
    Interval range(const Box3& box) const { return field->range(box); }
    double lipschitz(const Box3& box) const { return field->lipschitz(box); }
    Box3 bounds() const { return field->bounds(); }
    size_t termCount() const { return field->termCount(); }
};

}  // namespace isotrace::geometry
