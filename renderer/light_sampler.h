// Chooses one light for next-event estimation at a shading point, in
// proportion to its importance there (Light::importance: an estimate of the
// irradiance it may deliver, from distance and orientation bounds), so a
// lamp beside the point is not starved by a sky and a light behind the
// surface is never chosen.
//
// By default lights at finite distance sit in a light tree (light_tree.h)
// and are found in O(log n) importance evaluations; lights at infinity (the
// environment, the sun) stand beside the tree, which competes with them by
// its root's importance. "exhaustive" walks every light's own importance
// instead: exact proportions at O(n) per shading point. Neither allocates.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "renderer/light.h"
#include "renderer/light_tree.h"

namespace isotrace {

enum class LightSampling { Tree, Exhaustive };

/// The sampling a scene file names ("tree" or "exhaustive"); false for any
/// other name.
bool lightSamplingNamed(const std::string& name, LightSampling& sampling);

class LightSampler {
public:
    LightSampler() = default;
    explicit LightSampler(const std::vector<std::unique_ptr<const Light>>& lights,
                          LightSampling sampling = LightSampling::Tree);

    /// The sum of the importances the first choice is made between at
    /// `context` (every light's, or the lights at infinity and the tree's):
    /// compute it once per shading point for sample() and pmf().
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
    LightSampling sampling() const { return sampling_; }
    const LightTree& tree() const { return tree_; }

private:
    std::vector<const Light*> lights_;
    LightSampling sampling_ = LightSampling::Tree;
    /// Chosen among directly: every light, or (with a tree) those at
    /// infinity and those without bounds.
    std::vector<int> direct_;
    LightTree tree_;
};

}  // namespace isotrace
