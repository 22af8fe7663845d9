#include "renderer/light_sampler.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace isotrace {

namespace {
double safeImportance(const Light& light, const LightSampleContext& context) {
    const double w = light.importance(context);
    return std::isfinite(w) && w > 0 ? w : 0.0;
}
}  // namespace

double cosineBound(const Vec3& a, const Vec3& d, double slack) {
    const double angle = std::acos(std::clamp(a.dot(d), -1.0, 1.0));
    return std::cos(std::clamp(angle - slack, 0.0, std::numbers::pi));
}

double sphereHalfAngle(double r, double distance) {
    return distance <= r ? std::numbers::pi : std::asin(r / distance);
}

LightSampler::LightSampler(const std::vector<std::unique_ptr<const Light>>& lights) {
    for (const auto& light : lights) lights_.push_back(light.get());
}

int LightSampler::sample(const LightSampleContext& context, double u, double& pmf) const {
    double total = 0.0;
    int last = -1;
    for (size_t i = 0; i < lights_.size(); ++i)
        if (const double w = safeImportance(*lights_[i], context); w > 0) total += w, last = int(i);
    if (last < 0) return -1;
    const double target = u * total;
    double sum = 0.0;
    for (size_t i = 0; i < lights_.size(); ++i) {
        const double w = safeImportance(*lights_[i], context);
        sum += w;
        // The last light with weight catches a target past the rounded sum.
        if (w > 0 && (target < sum || int(i) == last)) {
            pmf = w / total;
            return int(i);
        }
    }
    return -1;  // unreachable
}

double LightSampler::pmf(const LightSampleContext& context, int index) const {
    double total = 0.0;
    for (const Light* light : lights_) total += safeImportance(*light, context);
    return total > 0 ? safeImportance(*lights_[index], context) / total : 0.0;
}

}  // namespace isotrace
