// Many spheres combined by one operation (a "scatter": foam, molecules,
// particles as solids), kept as one leaf instead of a tree of thousands of
// nodes. A cell prunes the set to the spheres that can decide its value
// there (Lipschitz pruning, after Barbier et al. 2025): for a union, those
// whose distance over the cell can come below the smallest upper bound of
// any; for a smooth union, within the blend radius of it; for an
// intersection, the mirror image. The pruned copy is exact inside the cell
// and holds only those spheres, so a cell costs what it holds, not the set.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "geometry/fields/sphere.h"

namespace isotrace::geometry {

enum class SetOperation { Union, SmoothUnion, Intersection };

/// A bounding hierarchy over spheres in Morton order: each node a run of
/// consecutive spheres, halved down to runs of a few. Large sets find the
/// spheres that matter in a box through it instead of testing every one,
/// so refining a million spheres costs each cell what it keeps.
struct SphereHierarchy {
    struct Node {
        Box3 centres;  ///< bounds of the run's sphere centres
        double largestRadius = 0.0;
        uint32_t begin = 0, end = 0;  ///< the run [begin, end) of the spheres
        uint32_t second = 0;          ///< the second child (the first follows the node); 0 at a leaf
    };
    std::vector<Node> nodes;  ///< depth first, the root first

    static SphereHierarchy over(const std::vector<SphereField>& spheres);
};

struct SphereSetField {
    SetOperation operation = SetOperation::Union;
    /// The smooth union's blend radius k. Its spheres are folded by the
    /// quadratic smooth minimum in increasing order of their distances, so
    /// the value does not depend on the order they are listed in, and a
    /// sphere k or more above the smallest distance changes nothing.
    double blend = 0.0;
    /// Every sphere of the set, shared by its pruned copies, in Morton
    /// order of their centres: the members of one cell lie close together
    /// in memory.
    std::shared_ptr<const std::vector<SphereField>> all;
    /// Which of them this copy holds (all, until pruned), in increasing order.
    std::vector<uint32_t> members;
    /// Over `all`, shared likewise.
    std::shared_ptr<const SphereHierarchy> hierarchy;
    /// The box this copy was pruned to (everywhere, until pruned): inside
    /// it, its members are those of the whole set that can matter.
    Box3 region = Box3::everything();

    /// A set of these spheres, sorted into Morton order, holding them all.
    static SphereSetField of(std::vector<SphereField> spheres, SetOperation operation, double blend = 0.0);

    const SphereField& sphere(size_t i) const { return (*all)[members[i]]; }
    double value(const Vec3& p) const;
    double valueAndGradient(const Vec3& p, Vec3& gradient) const;
    Interval range(const Box3& box) const;
    /// Every sphere's distance is 1-Lipschitz, and so are their minimum,
    /// maximum and smooth minimum (a convex combination of gradients).
    double lipschitz(const Box3&) const { return 1.0; }
    Box3 bounds() const;
    /// The same field inside `box`, with only the spheres that matter there.
    SphereSetField prunedTo(const Box3& box) const;
    /// The members (indices into `all`) that reach into `box`: all a ray
    /// inside it can enter or leave. Fewer than prunedTo keeps, which holds
    /// those that decide the value there too.
    std::vector<uint32_t> membersReaching(const Box3& box) const;
    size_t termCount() const { return members.size(); }

private:
    /// Large unions and smooth unions go through the hierarchy; the
    /// results are those of testing every member, to the bit.
    bool indexed(const Box3& box) const;
    Interval indexedRange(const Box3& box) const;
    double smallestHigh(const Box3& box) const;
};

}  // namespace isotrace::geometry
