#include "geometry/fields/sphere_set.h"

#include <algorithm>
#include <limits>

#include "geometry/smooth_min.h"

namespace isotrace::geometry {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Scratch storage, one per thread, grown once: evaluating a set allocates
// nothing in the steady state. Its own, not FieldProgram's: those buffers
// hold the program's slots while this leaf is evaluated.
template <class T>
std::vector<T>& scratch(size_t n) {
    thread_local std::vector<T> storage;
    if (storage.size() < n) storage.resize(std::max<size_t>(n, 64));
    return storage;
}

struct DistanceAndGradient {
    double distance;
    Vec3 gradient;
    bool operator<(const DistanceAndGradient& o) const { return distance < o.distance; }
};

// The smooth union of values given in increasing order: a fold of the
// smooth minimum, starting from the smallest.
double foldSorted(const double* values, size_t n, double k) {
    double partial = values[0];
    for (size_t i = 1; i < n; ++i) partial = smoothMin(partial, values[i], k).value;
    return partial;
}

// The smooth union of `values` (any order): only those below the smallest
// plus k can change the fold, so only they are sorted.
double smoothUnionOf(const double* values, size_t n, double k) {
    double smallest = kInfinity;
    for (size_t i = 0; i < n; ++i) smallest = std::min(smallest, values[i]);
    std::vector<double>& near = scratch<double>(n);
    size_t count = 0;
    for (size_t i = 0; i < n; ++i)
        if (values[i] < smallest + k) near[count++] = values[i];
    std::sort(near.begin(), near.begin() + long(count));
    return foldSorted(near.data(), count, k);
}

// Lists this long are queried through the hierarchy. Below it, testing
// each member costs less: a small cell's query visits some 50 leaves of 8
// spheres around it (bench/RESULTS.md, "Scale").
constexpr size_t kIndexedMembers = 4096;

using Node = SphereHierarchy::Node;

// Leeway for rounding: the node bounds below are those of one sphere's
// range at the run's nearest centre, so they can differ from the range of a
// member only by rounding.
double lowered(double bound, const Box3& box) {
    const double scale = std::abs(bound) + box.lower.cwiseAbs().maxCoeff() + box.upper.cwiseAbs().maxCoeff();
    return bound - 1e-12 * scale;
}

// At most the smallest lower end, over `box`, of the distance to any sphere
// of the node.
double lowestLow(const Node& node, const Box3& box) {
    const Vec3 gap = (node.centres.lower - box.upper).cwiseMax(box.lower - node.centres.upper).cwiseMax(0.0);
    return lowered(gap.norm() - node.largestRadius, box);
}

// At most the smallest upper end: the farthest corner is nearest from the
// centre closest to the box's middle.
double lowestHigh(const Node& node, const Box3& box) {
    const Vec3 c = box.center().cwiseMax(node.centres.lower).cwiseMin(node.centres.upper);
    const Vec3 farthest = (c - box.lower).cwiseAbs().cwiseMax((c - box.upper).cwiseAbs());
    return lowered(farthest.norm() - node.largestRadius, box);
}

enum class Order { NearerFirst, Increasing };

// Calls visit(i) for the spheres i under every node whose bound is at most
// limit(), which may fall as spheres are visited: nearer nodes first lowers
// it early; in increasing order the spheres come in the order of `all`.
template <class Bound, class Limit, class Visit>
void visitSpheresNear(const SphereHierarchy& hierarchy, Order order, Bound bound, Limit limit, Visit visit) {
    struct Pending {
        uint32_t node;
        double bound;
    };
    // One pending sibling per level: 64 levels hold 2^64 spheres.
    Pending stack[64];
    int top = 0;
    stack[top++] = {0, bound(hierarchy.nodes[0])};
    while (top > 0) {
        const Pending p = stack[--top];
        if (p.bound > limit()) continue;
        const Node& node = hierarchy.nodes[p.node];
        if (node.second == 0) {
            for (uint32_t i = node.begin; i < node.end; ++i) visit(i);
            continue;
        }
        Pending first{p.node + 1, bound(hierarchy.nodes[p.node + 1])};
        Pending second{node.second, bound(hierarchy.nodes[node.second])};
        if (order == Order::NearerFirst && second.bound < first.bound) std::swap(first, second);
        stack[top++] = second;
        stack[top++] = first;
    }
}

}  // namespace

// A copy pruned to `region` holds, of all spheres, those that matter there;
// inside `region` the spheres that matter to it are the same whether drawn
// from its list or from the whole set. A sphere left out of the list was,
// in some enclosing box, above the smallest upper end (plus k); in a box
// inside that one its lower end is no smaller and the smallest upper end no
// larger (rounding preserves both), so it stays out. Large lists are
// therefore queried through the whole set's hierarchy.
bool SphereSetField::indexed(const Box3& box) const {
    return hierarchy && members.size() > kIndexedMembers && operation != SetOperation::Intersection &&
           region.contains(box);
}

double SphereSetField::smallestHigh(const Box3& box) const {
    double smallest = kInfinity;
    visitSpheresNear(
        *hierarchy, Order::NearerFirst, [&](const Node& n) { return lowestHigh(n, box); }, [&] { return smallest; },
        [&](uint32_t i) { smallest = std::min(smallest, (*all)[i].range(box).hi); });
    return smallest;
}

double SphereSetField::value(const Vec3& p) const {
    switch (operation) {
        case SetOperation::Union: {
            double d = kInfinity;
            for (const uint32_t i : members) d = std::min(d, (*all)[i].value(p));
            return d;
        }
        case SetOperation::Intersection: {
            double d = -kInfinity;
            for (const uint32_t i : members) d = std::max(d, (*all)[i].value(p));
            return d;
        }
        case SetOperation::SmoothUnion: {
            // Two passes (distances are cheap): the smallest, then those
            // that can change the fold, sorted.
            double smallest = kInfinity;
            for (const uint32_t i : members) smallest = std::min(smallest, (*all)[i].value(p));
            std::vector<double>& near = scratch<double>(members.size());
            size_t count = 0;
            for (const uint32_t i : members)
                if (const double d = (*all)[i].value(p); d < smallest + blend) near[count++] = d;
            std::sort(near.begin(), near.begin() + long(count));
            return foldSorted(near.data(), count, blend);
        }
    }
    return kInfinity;
}

double SphereSetField::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    if (operation != SetOperation::SmoothUnion) {
        const bool isUnion = operation == SetOperation::Union;
        double best = isUnion ? kInfinity : -kInfinity;
        for (const uint32_t i : members) {
            Vec3 g;
            const double d = (*all)[i].valueAndGradient(p, g);
            if (isUnion ? d < best : d > best) best = d, gradient = g;
        }
        return best;
    }
    double smallest = kInfinity;
    for (const uint32_t i : members) smallest = std::min(smallest, (*all)[i].value(p));
    std::vector<DistanceAndGradient>& near = scratch<DistanceAndGradient>(members.size());
    size_t count = 0;
    for (const uint32_t i : members) {
        Vec3 g;
        const double d = (*all)[i].valueAndGradient(p, g);
        if (d < smallest + blend) near[count++] = {d, g};
    }
    std::sort(near.begin(), near.begin() + long(count));
    double partial = near[0].distance;
    gradient = near[0].gradient;
    for (size_t i = 1; i < count; ++i) {
        const SmoothMinResult r = smoothMin(partial, near[i].distance, blend);
        partial = r.value;
        gradient = r.h * gradient + (1.0 - r.h) * near[i].gradient;
    }
    return partial;
}

Interval SphereSetField::indexedRange(const Box3& box) const {
    if (operation == SetOperation::Union) {
        double low = kInfinity;
        visitSpheresNear(
            *hierarchy, Order::NearerFirst, [&](const Node& n) { return lowestLow(n, box); }, [&] { return low; },
            [&](uint32_t i) { low = std::min(low, (*all)[i].range(box).lo); });
        return Interval(low, smallestHigh(box));
    }
    // A smooth union: each end folds the ends within k of the smallest;
    // those gathered while the smallest was still falling are dropped by
    // the fold's own test.
    auto end = [&](bool upper, std::vector<double>& gathered) {
        gathered.clear();
        double smallest = kInfinity;
        visitSpheresNear(
            *hierarchy, Order::NearerFirst,
            [&](const Node& n) { return upper ? lowestHigh(n, box) : lowestLow(n, box); },
            [&] { return smallest + blend; },
            [&](uint32_t i) {
                const Interval r = (*all)[i].range(box);
                const double v = upper ? r.hi : r.lo;
                if (v < smallest + blend) gathered.push_back(v);
                smallest = std::min(smallest, v);
            });
        return smoothUnionOf(gathered.data(), gathered.size(), blend);
    };
    thread_local std::vector<double> lows, highs;
    return widened(Interval(end(false, lows), end(true, highs)));
}

Interval SphereSetField::range(const Box3& box) const {
    if (indexed(box)) return indexedRange(box);
    const size_t n = members.size();
    switch (operation) {
        case SetOperation::Union: {
            Interval r(kInfinity);
            for (const uint32_t i : members) r = min(r, (*all)[i].range(box));
            return r;
        }
        case SetOperation::Intersection: {
            Interval r(-kInfinity);
            for (const uint32_t i : members) r = max(r, (*all)[i].range(box));
            return r;
        }
        case SetOperation::SmoothUnion: {
            // Monotone in every distance: the ends come from the ends.
            thread_local std::vector<double> lows, highs;
            lows.resize(n);
            highs.resize(n);
            for (size_t i = 0; i < n; ++i) {
                const Interval r = sphere(i).range(box);
                lows[i] = r.lo, highs[i] = r.hi;
            }
            return widened(Interval(smoothUnionOf(lows.data(), n, blend), smoothUnionOf(highs.data(), n, blend)));
        }
    }
    return Interval(kInfinity);
}

Box3 SphereSetField::bounds() const {
    if (operation == SetOperation::Intersection) {
        Box3 box = Box3::everything();
        for (const uint32_t i : members) box = intersection(box, (*all)[i].bounds());
        return box;
    }
    Box3 box;
    for (const uint32_t i : members) box.extend((*all)[i].bounds());
    // Each fold lowers the smooth union by at most k/4, and only while it is
    // within k of the smallest distance: it stays above min - 5k/4.
    return operation == SetOperation::SmoothUnion ? box.expanded(1.25 * blend) : box;
}

SphereSetField SphereSetField::prunedTo(const Box3& box) const {
    if (indexed(box)) {
        // The spheres whose lower end is within the threshold below, found
        // near the box, in the order of `all`.
        const double threshold = smallestHigh(box) + (operation == SetOperation::SmoothUnion ? blend : 0.0);
        SphereSetField out{operation, blend, all, {}, hierarchy, box};
        visitSpheresNear(
            *hierarchy, Order::Increasing, [&](const Node& n) { return lowestLow(n, box); }, [&] { return threshold; },
            [&](uint32_t i) {
                const double low = (*all)[i].range(box).lo;
                if (operation == SetOperation::Union ? low <= threshold : low < threshold) out.members.push_back(i);
            });
        out.members.shrink_to_fit();
        return out;
    }
    std::vector<Interval>& ranges = scratch<Interval>(members.size());
    double smallestHigh = kInfinity, largestLow = -kInfinity;
    for (size_t i = 0; i < members.size(); ++i) {
        ranges[i] = sphere(i).range(box);
        smallestHigh = std::min(smallestHigh, ranges[i].hi);
        largestLow = std::max(largestLow, ranges[i].lo);
    }
    // A union's value in the box is at most smallestHigh everywhere: a
    // sphere never below it never decides the minimum; in a smooth union,
    // one k above it adds nothing to the fold; an intersection's mirror.
    auto matters = [&](const Interval& r) {
        switch (operation) {
            case SetOperation::Union: return r.lo <= smallestHigh;
            case SetOperation::SmoothUnion: return r.lo < smallestHigh + blend;
            case SetOperation::Intersection: return r.hi >= largestLow;
        }
        return true;
    };
    // Pruned from a list that was itself pruned to a box not holding this
    // one, the list may lack spheres the whole set has here: never indexed.
    SphereSetField out{operation, blend, all, {}, hierarchy, region.contains(box) ? box : Box3()};
    size_t kept = 0;
    for (size_t i = 0; i < members.size(); ++i) kept += matters(ranges[i]);
    out.members.reserve(kept);
    for (size_t i = 0; i < members.size(); ++i)
        if (matters(ranges[i])) out.members.push_back(members[i]);
    return out;
}

std::vector<uint32_t> SphereSetField::membersReaching(const Box3& box) const {
    std::vector<uint32_t> reaching;
    for (const uint32_t i : members)
        if ((*all)[i].range(box).lo <= 0.0) reaching.push_back(i);
    return reaching;
}

namespace {

// Three 21-bit coordinates interleaved: z-order of a point in the unit cube.
uint64_t mortonCode(const Vec3& unit) {
    auto spread = [](uint64_t x) {
        x &= 0x1fffff;
        x = (x | x << 32) & 0x1f00000000ffffULL;
        x = (x | x << 16) & 0x1f0000ff0000ffULL;
        x = (x | x << 8) & 0x100f00f00f00f00fULL;
        x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
        x = (x | x << 2) & 0x1249249249249249ULL;
        return x;
    };
    const Vec3 q = (unit.cwiseMax(0.0).cwiseMin(1.0) * double(0x1fffff));
    return spread(uint64_t(q.x())) | spread(uint64_t(q.y())) << 1 | spread(uint64_t(q.z())) << 2;
}

}  // namespace

SphereHierarchy SphereHierarchy::over(const std::vector<SphereField>& spheres) {
    // Runs this short are tested sphere by sphere.
    constexpr uint32_t kLeafSpheres = 8;
    SphereHierarchy h;
    if (spheres.empty()) return h;
    h.nodes.reserve(2 * (spheres.size() / kLeafSpheres + 1));
    auto build = [&](auto&& self, uint32_t begin, uint32_t end) -> void {
        const auto at = uint32_t(h.nodes.size());
        h.nodes.push_back({});
        Node node;
        node.begin = begin, node.end = end;
        if (end - begin <= kLeafSpheres) {
            for (uint32_t i = begin; i < end; ++i) {
                node.centres.extend(spheres[i].center);
                node.largestRadius = std::max(node.largestRadius, spheres[i].radius);
            }
        } else {
            const uint32_t middle = begin + (end - begin) / 2;
            self(self, begin, middle);
            node.second = uint32_t(h.nodes.size());
            self(self, middle, end);
            const Node &a = h.nodes[at + 1], &b = h.nodes[node.second];
            node.centres = unionOf(a.centres, b.centres);
            node.largestRadius = std::max(a.largestRadius, b.largestRadius);
        }
        h.nodes[at] = node;
    };
    build(build, 0, uint32_t(spheres.size()));
    return h;
}

SphereSetField SphereSetField::of(std::vector<SphereField> spheres, SetOperation operation, double blend) {
    Box3 box;
    for (const SphereField& s : spheres) box.extend(s.center);
    const Vec3 extent = box.extent().cwiseMax(1e-300);
    std::vector<std::pair<uint64_t, uint32_t>> order(spheres.size());
    for (size_t i = 0; i < spheres.size(); ++i)
        order[i] = {mortonCode((spheres[i].center - box.lower).cwiseQuotient(extent)), uint32_t(i)};
    std::sort(order.begin(), order.end());
    auto sorted = std::make_shared<std::vector<SphereField>>();
    sorted->reserve(spheres.size());
    for (const auto& [code, i] : order) sorted->push_back(spheres[i]);
    auto hierarchy = std::make_shared<SphereHierarchy>(SphereHierarchy::over(*sorted));
    SphereSetField set{operation, blend, std::move(sorted), {}, std::move(hierarchy)};
    set.members.resize(spheres.size());
    for (size_t i = 0; i < spheres.size(); ++i) set.members[i] = uint32_t(i);
    return set;
}

}  // namespace isotrace::geometry
