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

double cosineBound(const Vec3& a, const Vec3& d, double sinSlack) {
    // cos(theta - slack) for theta > slack, else 1; no trigonometric calls:
    // this runs for every light at every shading point.
    if (!(sinSlack < 1)) return 1.0;
    const double cosTheta = std::clamp(a.dot(d), -1.0, 1.0);
    const double cosSlack = std::sqrt(1 - sinSlack * sinSlack);
    if (cosTheta >= cosSlack) return 1.0;
    const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
    return cosTheta * cosSlack + sinTheta * sinSlack;
}

double sphereSinHalfAngle(double r, double distance) { return distance <= r ? 1.0 : r / distance; }

LightSampler::LightSampler(const std::vector<std::unique_ptr<const Light>>& lights) {
    for (const auto& light : lights) lights_.push_back(light.get());
}

double LightSampler::totalImportance(const LightSampleContext& context) const {
    double total = 0.0;
    for (const Light* light : lights_) total += safeImportance(*light, context);
    return total;
}

int LightSampler::sample(const LightSampleContext& context, double u, double total, double& pmf) const {
    if (!(total > 0)) return -1;
    const double target = u * total;
    double sum = 0.0;
    for (size_t i = 0; i < lights_.size(); ++i) {
        const double w = safeImportance(*lights_[i], context);
        sum += w;
        if (w > 0 && target < sum) {
            pmf = w / total;
            return int(i);
        }
    }
    // A target past the rounded sum: the last light with weight.
    for (size_t i = lights_.size(); i-- > 0;)
        if (const double w = safeImportance(*lights_[i], context); w > 0) {
            pmf = w / total;
            return int(i);
        }
    return -1;
}

double LightSampler::pmf(const LightSampleContext& context, int index, double total) const {
    return total > 0 ? safeImportance(*lights_[index], context) / total : 0.0;
}

}  // namespace isotrace
