#include "renderer/light_sampler.h"

#include <algorithm>
#include <optional>

namespace isotrace {

double sphereSinHalfAngle(double r, double distance) { return distance <= r ? 1.0 : r / distance; }

bool lightSamplingNamed(const std::string& name, LightSampling& sampling) {
    if (name == "tree") sampling = LightSampling::Tree;
    else if (name == "exhaustive") sampling = LightSampling::Exhaustive;
    else return false;
    return true;
}

LightSampler::LightSampler(const std::vector<std::unique_ptr<const Light>>& lights, LightSampling sampling)
    : sampling_(sampling) {
    for (const auto& light : lights) lights_.push_back(light.get());
    std::vector<int> bounded;
    std::vector<LightBounds> bounds(lights_.size());
    for (size_t i = 0; i < lights_.size(); ++i) {
        const std::optional<LightBounds> b = sampling == LightSampling::Tree ? lights_[i]->bounds() : std::nullopt;
        if (b && b->power > 0 && b->box.isFinite() && !b->box.isEmpty()) {
            bounds[i] = *b;
            bounded.push_back(int(i));
        } else {
            direct_.push_back(int(i));
        }
    }
    tree_ = LightTree(lights_, bounded, bounds);
}

double LightSampler::totalImportance(const LightSampleContext& context) const {
    double total = tree_.importance(context);
    for (const int i : direct_) total += samplingWeight(lights_[size_t(i)]->importance(context));
    return total;
}

int LightSampler::sample(const LightSampleContext& context, double u, double total, double& pmf) const {
    if (!(total > 0)) return -1;
    const double target = u * total;
    double sum = 0.0;
    int last = -1;
    double lastWeight = 0.0;
    for (const int i : direct_) {
        const double w = samplingWeight(lights_[size_t(i)]->importance(context));
        sum += w;
        if (w > 0 && target < sum) {
            pmf = w / total;
            return i;
        }
        if (w > 0) last = i, lastWeight = w;
    }
    // With no light beside the tree the total is the root's importance, to
    // the bit: it is not weighed again.
    const double treeWeight = direct_.empty() ? total : tree_.importance(context);
    if (treeWeight > 0) {
        // The rest of [0, total) is the tree's: rescaled, u chooses in it.
        const double v = std::clamp((target - sum) / treeWeight, 0.0, kLargestBelowOne);
        double within = 0.0;
        const int chosen = tree_.sample(context, v, within);
        if (chosen < 0) return -1;
        pmf = treeWeight / total * within;
        return chosen;
    }
    // A target past the rounded sum: the last light with weight.
    if (last < 0) return -1;
    pmf = lastWeight / total;
    return last;
}

double LightSampler::pmf(const LightSampleContext& context, int index, double total) const {
    if (!(total > 0)) return 0.0;
    if (tree_.contains(index))
        return (direct_.empty() ? 1.0 : tree_.importance(context) / total) * tree_.pmf(context, index);
    return samplingWeight(lights_[size_t(index)]->importance(context)) / total;
}

}  // namespace isotrace
