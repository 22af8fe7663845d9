// Chooses one light for next-event estimation at a shading point, in
// proportion to each light's importance there (Light::importance: an
// estimate of the irradiance it may deliver, from distance and
// orientation bounds), so a lamp beside the point is not starved by a sky
// and a light behind the surface is never chosen. A shading point walks
// the lights twice (the total, then the choice) and allocates nothing.
#pragma once

#include <memory>
#include <vector>

#include "renderer/light.h"

namespace isotrace {

class LightSampler {
public:
    LightSampler() = default;
    explicit LightSampler(const std::vector<std::unique_ptr<const Light>>& lights);

    /// The sum of the lights' importances at `context`: compute it once per
    /// shading point for sample() and pmf().
    double totalImportance(const LightSampleContext& context) const;
    /// The light chosen by u in [0, 1) at `context` (its probability in
    /// `pmf`), or -1 when no light can light it.
    int sample(const LightSampleContext& context, double u, double total, double& pmf) const;
    int sample(const LightSampleContext& context, double u, double& pmf) const {
        return sample(context, u, totalImportance(context), pmf);
    }
    /// Probability that sample() chooses light `index` at `context`.
    double pmf(const LightSampleContext& context, int index, double total) const;
    double pmf(const LightSampleContext& context, int index) const {
        return pmf(context, index, totalImportance(context));
    }
    size_t size() const { return lights_.size(); }

private:
    std::vector<const Light*> lights_;
};

}  // namespace isotrace
