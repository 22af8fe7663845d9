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

}  // namespace

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

Interval SphereSetField::range(const Box3& box) const {
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
    SphereSetField out{operation, blend, all, {}};
    size_t kept = 0;
    for (size_t i = 0; i < members.size(); ++i) kept += matters(ranges[i]);
    out.members.reserve(kept);
    for (size_t i = 0; i < members.size(); ++i)
        if (matters(ranges[i])) out.members.push_back(members[i]);
    return out;
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
    SphereSetField set{operation, blend, std::move(sorted), {}};
    set.members.resize(spheres.size());
    for (size_t i = 0; i < spheres.size(); ++i) set.members[i] = uint32_t(i);
    return set;
}

}  // namespace isotrace::geometry
