#include "renderer/light_tree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace isotrace {

namespace {

constexpr int kBuckets = 12;

double surfaceArea(const geometry::Box3& box) {
    const Vec3 e = box.extent().cwiseMax(0.0);
    return 2 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
}

}  // namespace

LightTree::LightTree(const std::vector<const Light*>& lights, const std::vector<int>& members,
                     const std::vector<LightBounds>& bounds)
    : lights_(lights), leafOfLight_(lights.size(), -1) {
    if (members.empty()) return;
    std::vector<int> order = members;
    nodes_.reserve(2 * order.size() - 1);
    nodes_.emplace_back();
    build(order, 0, order.size(), bounds, 0);
}

void LightTree::build(std::vector<int>& members, size_t begin, size_t end, const std::vector<LightBounds>& bounds,
                      int32_t index) {
    if (end - begin == 1) {
        const int light = members[begin];
        nodes_[size_t(index)].bounds = PreparedLightBounds(bounds[size_t(light)]);
        nodes_[size_t(index)].light = light;
        leafOfLight_[size_t(light)] = index;
        return;
    }

    LightBounds all;
    geometry::Box3 centroids;
    for (size_t i = begin; i < end; ++i) {
        all = unite(all, bounds[members[i]]);
        centroids.extend(bounds[members[i]].box.center());
    }
    // The surface area orientation heuristic: a split costs what its two
    // sides' power, cone measure and box area predict a sample pays to tell
    // them apart; thin boxes are discouraged along their long axis (Kr).
    // Lights on a line or at one point have no area: their extent stands in.
    const bool flat = !(surfaceArea(all.box) > 0);
    auto boxMeasure = [flat](const geometry::Box3& b) { return flat ? b.extent().cwiseMax(0.0).sum() : surfaceArea(b); };
    auto cost = [&](const LightBounds& b) { return b.power > 0 ? b.power * b.orientationMeasure() * boxMeasure(b.box) : 0.0; };
    const Vec3 extent = all.box.extent();
    double bestCost = std::numeric_limits<double>::infinity();
    int bestAxis = -1, bestSplit = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const double width = centroids.upper[axis] - centroids.lower[axis];
        if (!(width > 0)) continue;
        std::array<LightBounds, kBuckets> buckets;
        for (size_t i = begin; i < end; ++i) {
            const LightBounds& b = bounds[members[i]];
            const int k = std::min(kBuckets - 1, int(kBuckets * (b.box.center()[axis] - centroids.lower[axis]) / width));
            buckets[k] = unite(buckets[k], b);
        }
        std::array<double, kBuckets> belowCost{};
        LightBounds below;
        for (int k = 0; k + 1 < kBuckets; ++k) belowCost[k + 1] = cost(below = unite(below, buckets[k]));
        LightBounds above;
        const double stretch = extent.maxCoeff() / std::max(extent[axis], 1e-300);
        for (int split = kBuckets - 1; split >= 1; --split) {
            above = unite(above, buckets[split]);
            const double c = stretch * (belowCost[split] + cost(above));
            if (c < bestCost) bestCost = c, bestAxis = axis, bestSplit = split;
        }
    }

    size_t middle = begin + (end - begin) / 2;
    if (bestAxis >= 0) {
        const double lower = centroids.lower[bestAxis], width = centroids.upper[bestAxis] - lower;
        const auto split = std::partition(members.begin() + long(begin), members.begin() + long(end), [&](int light) {
            return std::min(kBuckets - 1, int(kBuckets * (bounds[light].box.center()[bestAxis] - lower) / width)) < bestSplit;
        });
        const auto at = size_t(split - members.begin());
        if (at > begin && at < end) middle = at;
    }
    const auto first = int32_t(nodes_.size());
    nodes_.emplace_back();
    nodes_.emplace_back();
    nodes_[size_t(index)].children[0] = first;
    nodes_[size_t(index)].children[1] = first + 1;
    nodes_[size_t(index)].bounds = PreparedLightBounds(all);
    nodes_[size_t(first)].parent = nodes_[size_t(first) + 1].parent = index;
    build(members, begin, middle, bounds, first);
    build(members, middle, end, bounds, first + 1);
}

double LightTree::nodeImportance(int32_t node, const LightSampleContext& context) const {
    const Node& n = nodes_[size_t(node)];
    return samplingWeight(n.isLeaf() ? lights_[size_t(n.light)]->importance(context) : n.bounds.importance(context));
}

int LightTree::sample(const LightSampleContext& context, double u, double& pmf) const {
    pmf = 0.0;
    if (empty()) return -1;
    double probability = 1.0;
    int32_t node = 0;
    while (!nodes_[size_t(node)].isLeaf()) {
        const Node& n = nodes_[size_t(node)];
        const double first = nodeImportance(n.children[0], context);
        const double second = nodeImportance(n.children[1], context);
        const double sum = first + second;
        if (!(sum > 0)) return -1;
        const double pFirst = first / sum, pSecond = second / sum;
        if (u < pFirst) {
            u = std::min(u / pFirst, kLargestBelowOne);
            probability *= pFirst;
            node = n.children[0];
        } else {
            u = std::min((u - pFirst) / pSecond, kLargestBelowOne);
            probability *= pSecond;
            node = n.children[1];
        }
    }
    if (nodes_.size() == 1 && !(nodeImportance(0, context) > 0)) return -1;
    pmf = probability;
    return nodes_[size_t(node)].light;
}

double LightTree::pmf(const LightSampleContext& context, int index) const {
    if (!contains(index)) return 0.0;
    int32_t node = leafOfLight_[size_t(index)];
    double probability = 1.0;
    for (int32_t parent = nodes_[size_t(node)].parent; parent >= 0; node = parent, parent = nodes_[size_t(node)].parent) {
        const Node& p = nodes_[size_t(parent)];
        const int32_t sibling = p.children[0] == node ? p.children[1] : p.children[0];
        const double own = nodeImportance(node, context);
        if (!(own > 0)) return 0.0;
        probability *= own / (own + nodeImportance(sibling, context));
    }
    return probability;
}

int LightTree::depth() const {
    int deepest = 0;
    for (size_t i = 0; i < nodes_.size(); ++i) {
        if (!nodes_[i].isLeaf()) continue;
        int levels = 1;
        for (int32_t n = nodes_[i].parent; n >= 0; n = nodes_[size_t(n)].parent) ++levels;
        deepest = std::max(deepest, levels);
    }
    return deepest;
}

}  // namespace isotrace
