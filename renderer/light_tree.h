// A bounding volume hierarchy over lights for next-event estimation, after
// Conty Estevez and Kulla (2018) and pbrt-v4's BVHLightSampler: each node
// bounds its lights' box, power and cone of emission (LightBounds), and a
// sample descends from the root, choosing each child in proportion to its
// importance at the shading point. A light is found in O(log n) importance
// evaluations instead of n, and the probability of choosing it is the
// product of the choices on its way, which pmf() retraces from its leaf.
// At a leaf the light's own importance (Light::importance), tighter than
// its bounds, stands for them.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "renderer/light.h"
#include "renderer/light_bounds.h"

namespace isotrace {

/// The largest double below 1: a u rescaled into a chosen interval stays in
/// [0, 1).
inline constexpr double kLargestBelowOne = 1.0 - std::numeric_limits<double>::epsilon() / 2;

class LightTree {
public:
    LightTree() = default;
    /// A tree over `members`, indices into `lights`; `bounds` holds each
    /// light's bounds at its index.
    LightTree(const std::vector<const Light*>& lights, const std::vector<int>& members,
              const std::vector<LightBounds>& bounds);

    bool empty() const { return nodes_.empty(); }
    /// The importance of the whole tree at `context` (its root's).
    double importance(const LightSampleContext& context) const { return empty() ? 0.0 : nodeImportance(0, context); }
    /// A light chosen by u in [0, 1), or -1 when none can light `context`;
    /// `pmf` is its probability given that the tree was chosen.
    int sample(const LightSampleContext& context, double u, double& pmf) const;
    /// The probability that sample() chooses light `index` (a member).
    double pmf(const LightSampleContext& context, int index) const;
    bool contains(int index) const { return size_t(index) < leafOfLight_.size() && leafOfLight_[index] >= 0; }
    size_t nodeCount() const { return nodes_.size(); }
    /// Levels from the root to the deepest leaf (1 for one light).
    int depth() const;

private:
    // A node's children sit side by side: a sample weighs both at once.
    struct Node {
        PreparedLightBounds bounds;
        int32_t parent = -1;
        int32_t children[2] = {-1, -1};  ///< both -1 at a leaf
        int32_t light = -1;              ///< a leaf's light
        bool isLeaf() const { return light >= 0; }
    };

    void build(std::vector<int>& members, size_t begin, size_t end, const std::vector<LightBounds>& bounds, int32_t index);
    double nodeImportance(int32_t node, const LightSampleContext& context) const;

    std::vector<const Light*> lights_;
    std::vector<Node> nodes_;
    std::vector<int32_t> leafOfLight_;  ///< by light index; -1 for lights outside the tree
};

}  // namespace isotrace
