#include "geometry/pointsets/mpu_field.h"
#include "geometry/pointsets/mpu_lane_kernels.h"
#include "geometry/pointsets/mpu_numerator_model.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/point_grid.h"

namespace isotrace::geometry {

namespace {

void orthonormalFrame(const Vec3& n, Vec3& u, Vec3& v) {
    u = n.unitOrthogonal();
    v = n.cross(u);
}

}  // namespace

namespace {
Interval maxOf(Interval a, Interval b) { return {std::max(a.lo, b.lo), std::max(a.hi, b.hi)}; }
Interval minOf(Interval a, Interval b) { return {std::min(a.lo, b.lo), std::min(a.hi, b.hi)}; }
}  // namespace

Interval MpuQuadric::range(const Box3& box) const {
    // About the box's centre c: Q(c + y) = Q(c) + grad Q(c) . y + y^T A y
    // with |y_k| <= h_k. Each term is bounded once; the plain interval
    // extension in x - origin bounds g . y and y^T A y apart, losing their
    // cancellation, and costs twice as much.
    Vec3 gradient;
    const double value = evaluate(box.center(), &gradient);
    return widened(quadraticRange(value, gradient, A, 0.5 * box.extent()));
}

double MpuQuadric::gradientBound(const Box3& box) const {
    Interval y[3];
    for (int k = 0; k < 3; ++k) y[k] = {box.lower[k] - origin[k], box.upper[k] - origin[k]};
    double sum = 0;
    for (int k = 0; k < 3; ++k) {
        Interval d{g[k], g[k]};
        for (int l = 0; l < 3; ++l) d += (2.0 * A(k, l)) * y[l];
        sum += d.magnitude() * d.magnitude();
    }
    return std::sqrt(sum) * (1 + 1e-12);
}

namespace {

// max/min of pieces, with the gradient of the piece chosen (one-sided at a
// crease, as for CSG).
struct PieceValue {
    double value = 0.0;
    Vec3 gradient = Vec3::Zero();
};
PieceValue larger(const PieceValue& a, const PieceValue& b) { return a.value >= b.value ? a : b; }
PieceValue smaller(const PieceValue& a, const PieceValue& b) { return a.value <= b.value ? a : b; }

double largerValue(double a, double b) { return std::max(a, b); }
double smallerValue(double a, double b) { return std::min(a, b); }

}  // namespace

double MpuField::evaluate(const Local& l, const Vec3& x, Vec3* gradient) const {
    if (l.combination == MpuCombination::Interpolant) {
        const VariationalField& f = interpolants_[l.first];
        if (!gradient) return f.value(x);
        return f.valueAndGradient(x, *gradient);
    }
    const MpuQuadric* q = &pieces_[l.first];
    if (l.combination == MpuCombination::Single) return q[0].evaluate(x, gradient);
    PieceValue v[3]{};
    for (int k = 0; k < l.count; ++k) v[k].value = q[k].evaluate(x, &v[k].gradient);
    const PieceValue r = combineMpuPieces(l, v, larger, smaller);
    if (gradient) *gradient = r.gradient;
    return r.value;
}

Interval MpuField::range(const Local& l, const Box3& box) const {
    if (l.combination == MpuCombination::Interpolant) return interpolants_[l.first].range(box);
    const MpuQuadric* q = &pieces_[l.first];
    if (l.combination == MpuCombination::Single) return q[0].range(box);
    Interval v[3]{};
    for (int k = 0; k < l.count; ++k) v[k] = q[k].range(box);
    return combineMpuPieces(l, v, maxOf, minOf);
}

// A max or min of pieces is Lipschitz with the largest of their constants.
double MpuField::gradientBound(const Local& l, const Box3& box) const {
    if (l.combination == MpuCombination::Interpolant) return interpolants_[l.first].lipschitz(box);
    double bound = 0;
    for (int k = 0; k < l.count; ++k) bound = std::max(bound, pieces_[l.first + k].gradientBound(box));
    return bound;
}

namespace {

// |value| / |gradient|: a point's first-order distance to the zero set,
// how fits are judged at their points.
double firstOrderDistance(double value, const Vec3& gradient) {
    return std::abs(value) / std::max(gradient.norm(), 1e-300);
}

// Balls holding more points fit their functions to an even subsample of this many.
constexpr size_t kMaxBallFitPoints = 4096;

// A grown ball's support ends at the nearest point its function misses by
// more than this many times the accuracy. The worst point over the
// diagonal, trimming at 1, 2, 4 and 8 times the accuracy, and not at all:
//   kitten scan's untrimmed fit polygonized (37,822 vertices):
//     6.7e-4, 7.9e-4, 7.6e-4, 8.5e-4, 3.4e-3;
//   kitten scan: 3.1e-3, 2.9e-3, 3.5e-3, 3.4e-3, 3.7e-3;
//   oni.pwn (accuracy 1e-3): 9.1e-3, 8.1e-3, 3.1e-3, 4.6e-3, 5.6e-3.
// Near thin parts of sparse data a local that misses by a little is still
// the best there is.
constexpr double kGrownBallMiss = 4.0;

// Normals closer than this (cosine of about 26 degrees, the paper's
// threshold) belong to one side of a sharp feature.
constexpr double kSameSideCos = 0.9;

// The fits of one cell's ball: `near` are the points in it, weighted by
// their distance to the cell's centre.
class BallFit {
public:
    BallFit(const std::vector<MpuPoint>& points, const std::vector<uint32_t>& near, const Vec3& center, double radius)
        : points_(points), near_(near), radius_(radius) {
        weights_.resize(near.size());
        for (size_t k = 0; k < near.size(); ++k)
            weights_[k] = std::max(mpuWeight((points[near[k]].position - center).squaredNorm(), radius * radius), 1e-12);
    }

    /// Weighted centroid and mean unit normal of the points whose index in
    /// `near` is listed in `members`; false when the normals cancel.
    bool moments(const std::vector<uint32_t>& members, Vec3& centroid, Vec3& normal) const {
        double total = 0;
        centroid = normal = Vec3::Zero();
        for (uint32_t k : members) {
            total += weights_[k];
            centroid += weights_[k] * points_[near_[k]].position;
            normal += weights_[k] * points_[near_[k]].normal.normalized();
        }
        centroid /= total;
        if (!(normal.norm() > 1e-9 * total)) return false;
        normal.normalize();
        return true;
    }

    /// A height function h(s, t) = a s^2 + b s t + c t^2 + d s + e t + f
    /// over the plane through `centroid` normal to `normal`, as the quadric
    /// n.y - h(u.y, v.y); a plane when fewer than 6 points (a single
    /// oriented point already fixes one).
    MpuQuadric heightFunction(const std::vector<uint32_t>& members, const Vec3& centroid, const Vec3& normal) const {
        MpuQuadric q;
        q.origin = centroid;
        q.g = normal;
        if (members.size() < 6) return q;
        Vec3 u, v;
        orthonormalFrame(normal, u, v);
        const double scale = 1.0 / radius_;  // fits in conditioned coordinates
        Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
        Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
        for (uint32_t k : members) {
            const Vec3 y = (points_[near_[k]].position - centroid) * scale;
            const double s = y.dot(u), t = y.dot(v), h = y.dot(normal), w = weights_[k];
            Eigen::Matrix<double, 6, 1> row;
            row << s * s, s * t, t * t, s, t, 1.0;
            M += w * row * row.transpose();
            rhs += w * h * row;
        }
        M.diagonal().array() += 1e-9 * std::max(M.trace(), 1e-300);
        Eigen::Matrix<double, 6, 1> x = M.ldlt().solve(rhs);
        if (!x.allFinite()) x.setZero();
        // In world units h = radius H(s / radius, t / radius).
        const double a = x[0] / radius_, b = x[1] / radius_, c = x[2] / radius_;
        q.A = -(a * u * u.transpose() + 0.5 * b * (u * v.transpose() + v * u.transpose()) + c * v * v.transpose());
        // Symmetric to the last bit ((a u_i) u_j and (a u_j) u_i may round
        // apart): a saved fit keeps the upper triangle, and a fit loaded
        // from the cache must evaluate as the fresh one did.
        q.A = (0.5 * (q.A + q.A.transpose())).eval();
        q.g = normal - x[3] * u - x[4] * v;
        q.c0 = -x[5] * radius_;
        return q;
    }

    /// A general quadric: zero at the points, +delta and -delta at
    /// auxiliary points delta along and against their normals.
    MpuQuadric generalQuadric(const Vec3& centroid) const {
        const double scale = 1.0 / radius_;
        Eigen::Matrix<double, 10, 10> M = Eigen::Matrix<double, 10, 10>::Zero();
        Eigen::Matrix<double, 10, 1> rhs = Eigen::Matrix<double, 10, 1>::Zero();
        const double delta = 0.1;  // in conditioned units: a tenth of the ball's radius
        for (size_t k = 0; k < near_.size(); ++k) {
            const Vec3 q = (points_[near_[k]].position - centroid) * scale, n = points_[near_[k]].normal.normalized();
            for (int side = -1; side <= 1; ++side) {
                const Vec3 y = q + side * delta * n;
                Eigen::Matrix<double, 10, 1> row;
                row << y.x() * y.x(), y.y() * y.y(), y.z() * y.z(), 2 * y.x() * y.y(), 2 * y.x() * y.z(), 2 * y.y() * y.z(),
                    y.x(), y.y(), y.z(), 1.0;
                M += weights_[k] * row * row.transpose();
                rhs += weights_[k] * (side * delta) * row;
            }
        }
        M.diagonal().array() += 1e-9 * std::max(M.trace(), 1e-300);
        Eigen::Matrix<double, 10, 1> x = M.ldlt().solve(rhs);
        if (!x.allFinite()) x.setZero();
        // Back to world units: Q(y) = radius Qc(y / radius).
        MpuQuadric q;
        q.origin = centroid;
        q.A << x[0], x[3], x[4], x[3], x[1], x[5], x[4], x[5], x[2];
        q.A /= radius_;
        q.g = Vec3(x[6], x[7], x[8]);
        q.c0 = x[9] * radius_;
        return q;
    }

    /// The ball's normals in two or three clusters (sides of an edge or a
    /// corner), by farthest seeds and a few rounds of k-means on the
    /// sphere; fewer than two clusters when the normals all agree.
    std::vector<std::vector<uint32_t>> normalClusters(const Vec3& meanNormal) const {
        auto normalAt = [&](size_t k) { return points_[near_[k]].normal.normalized(); };
        auto farthestFrom = [&](auto&& closeness) {
            size_t best = 0;
            double lowest = 2;
            for (size_t k = 0; k < near_.size(); ++k)
                if (const double c = closeness(normalAt(k)); c < lowest) lowest = c, best = k;
            return std::pair{best, lowest};
        };
        std::vector<Vec3> seeds;
        const Vec3 a = normalAt(farthestFrom([&](const Vec3& n) { return n.dot(meanNormal); }).first);
        const auto [bIndex, ab] = farthestFrom([&](const Vec3& n) { return n.dot(a); });
        if (ab > kSameSideCos) return {};
        const Vec3 b = normalAt(bIndex);
        seeds = {a, b};
        const auto [cIndex, cFar] = farthestFrom([&](const Vec3& n) { return std::max(n.dot(a), n.dot(b)); });
        if (cFar < kSameSideCos) seeds.push_back(normalAt(cIndex));
        std::vector<std::vector<uint32_t>> clusters;
        for (int round = 0; round < 5; ++round) {
            clusters.assign(seeds.size(), {});
            for (size_t k = 0; k < near_.size(); ++k) {
                const Vec3 n = normalAt(k);
                size_t best = 0;
                for (size_t s = 1; s < seeds.size(); ++s)
                    if (n.dot(seeds[s]) > n.dot(seeds[best])) best = s;
                clusters[best].push_back(uint32_t(k));
            }
            for (size_t s = 0; s < seeds.size(); ++s) {
                Vec3 sum = Vec3::Zero();
                for (uint32_t k : clusters[s]) sum += weights_[k] * normalAt(k);
                if (sum.norm() > 0) seeds[s] = sum.normalized();
            }
        }
        // A feature is a jump of the normals. Two clusters with more than a
        // few normals within the threshold of each other's mean only cut a
        // spread where the normals turn gradually (a curved side, or a
        // sphere's cap seen whole): they are one side. A ball left with one
        // side is smooth and goes to smooth functions at a finer level.
        const size_t fewBetween = std::max<size_t>(1, near_.size() / 50);
        auto continuous = [&](size_t s, size_t o) {
            size_t between = 0;
            for (uint32_t k : clusters[s]) between += normalAt(k).dot(seeds[o]) > kSameSideCos;
            for (uint32_t k : clusters[o]) between += normalAt(k).dot(seeds[s]) > kSameSideCos;
            return between > fewBetween;
        };
        for (size_t s = 0; s < clusters.size(); ++s)
            for (size_t o = s + 1; o < clusters.size(); ++o)
                if (!clusters[s].empty() && !clusters[o].empty() && continuous(s, o)) {
                    clusters[s].insert(clusters[s].end(), clusters[o].begin(), clusters[o].end());
                    clusters[o].clear();
                }
        std::erase_if(clusters, [](const std::vector<uint32_t>& c) { return c.empty(); });
        if (clusters.size() < 2) return {};
        return clusters;
    }

    /// Largest first-order distance of the ball's points to the zero set
    /// of `value` (a function returning the value and filling the gradient).
    template <class Function>
    double error(Function&& value) const {
        return largestDistance(points_, near_, value);
    }

    /// The same over any list of points.
    template <class Function>
    static double largestDistance(const std::vector<MpuPoint>& points, const std::vector<uint32_t>& which,
                                  Function&& value) {
        double worst = 0;
        for (uint32_t i : which) {
            Vec3 g;
            const double q = value(points[i].position, g);
            worst = std::max(worst, firstOrderDistance(q, g));
        }
        return worst;
    }

private:
    const std::vector<MpuPoint>& points_;
    const std::vector<uint32_t>& near_;
    double radius_;
    std::vector<double> weights_;
};

}  // namespace

MpuField MpuField::fit(const std::vector<MpuPoint>& points, const MpuOptions& options, MpuReport* report) {
    const auto start = std::chrono::steady_clock::now();
    if (!(options.support > 0.5) || !(options.support <= 4)) throw std::invalid_argument("the support must lie in (0.5, 4]");
    if (!(options.accuracy > 0) || !(options.accuracy < 1)) throw std::invalid_argument("the accuracy must lie in (0, 1)");
    if (options.minPoints < 6) throw std::invalid_argument("a ball needs at least 6 points for a quadratic");
    if (points.size() < size_t(options.minPoints))
        throw std::invalid_argument("an MPU fit needs at least " + std::to_string(options.minPoints) + " points, found " +
                                    std::to_string(points.size()));
    Box3 box;
    for (const MpuPoint& p : points) {
        if (!p.position.allFinite() || !p.normal.allFinite() || !(p.normal.norm() > 0))
            throw std::invalid_argument("a point or normal is not finite, or a normal is zero");
        box.extend(p.position);
    }
    const double diagonal = box.extent().norm();
    if (!(diagonal > 0)) throw std::invalid_argument("all points coincide");
    const double tolerance = options.accuracy * diagonal;

    MpuField field;
    field.support_ = options.support;
    field.backgroundMargin_ = 1e-3 * diagonal;
    // The root cube: the points' box, centred, 30% wider, so the surface stays inside.
    const double half = 0.65 * box.extent().maxCoeff();
    field.domain_ = Box3::around(box.center(), half);
    std::vector<Vec3> positions(points.size());
    for (size_t i = 0; i < points.size(); ++i) positions[i] = points[i].position;
    const PointGrid index(positions, field.domain_, PointGrid::resolutionFor(points.size()));
    MpuReport r;
    std::vector<uint32_t> near, sample;

    // Depth-first over the octree with an explicit stack of cells.
    struct Cell {
        Vec3 center;
        double half;
        int depth;
    };
    std::vector<Cell> stack{{field.domain_.center(), half, 0}};
    while (!stack.empty()) {
        const Cell cell = stack.back();
        stack.pop_back();
        r.depth = std::max(r.depth, cell.depth);
        const double baseRadius = options.support * 2.0 * std::sqrt(3.0) * cell.half;
        double radius = baseRadius;
        index.within(cell.center, radius, near);
        while (near.size() < size_t(options.minPoints) && radius < 4 * diagonal) {
            radius *= 1.5;
            index.within(cell.center, radius, near);
        }
        // A cell whose ball had to grow lies away from the data: smaller
        // cells there would see the same points again. It keeps its fit.
        const bool deepest = cell.depth >= options.maxDepth || radius > baseRadius;
        // The shallow cells' balls hold most of the input: their functions
        // are fitted to an even subsample (a quadric has ten coefficients;
        // thousands of points fix it), and accepted only if they meet the
        // accuracy at every point of the ball. Without it a 1M-point fit
        // took 25x the time of a 100k-point one, in cells that split anyway.
        const std::vector<uint32_t>* fitted = &near;
        if (near.size() > kMaxBallFitPoints) {
            sample.clear();
            const double stride = double(near.size()) / double(kMaxBallFitPoints);
            for (size_t k = 0; k < kMaxBallFitPoints; ++k) sample.push_back(near[size_t(double(k) * stride)]);
            fitted = &sample;
        }
        const BallFit ball(points, *fitted, cell.center, radius);
        std::vector<uint32_t> all(fitted->size());
        for (size_t k = 0; k < all.size(); ++k) all[k] = uint32_t(k);
        Vec3 centroid, normal;
        const bool normalsAgree = ball.moments(all, centroid, normal);
        double agreement = normalsAgree ? 1.0 : -1.0;
        for (uint32_t i : *fitted) agreement = std::min(agreement, points[i].normal.normalized().dot(normal));
        const bool general = agreement < 0.2;
        const MpuQuadric smooth = general ? ball.generalQuadric(centroid) : ball.heightFunction(all, centroid, normal);
        double error = ball.error([&](const Vec3& p, Vec3& g) { return smooth.evaluate(p, &g); });

        Local local;
        local.center = cell.center;
        local.radius = radius;
        local.first = uint32_t(field.pieces_.size());
        std::vector<MpuQuadric> chosen{smooth};
        // Where a smooth function misses, an edge or corner may be the cause:
        // one height function per cluster of normals, joined by max where
        // the edge is convex (each side's centroid inside the other's
        // function) and by min where it is concave.
        if (error > tolerance && options.sharpFeatures) {
            const std::vector<std::vector<uint32_t>> clusters = ball.normalClusters(normal);
            if (clusters.size() >= 2) {
                std::vector<MpuQuadric> sides;
                std::vector<Vec3> centroids;
                for (const std::vector<uint32_t>& c : clusters) {
                    Vec3 cc, cn;
                    if (!ball.moments(c, cc, cn)) break;
                    sides.push_back(ball.heightFunction(c, cc, cn));
                    centroids.push_back(cc);
                }
                if (sides.size() == clusters.size()) {
                    auto convex = [&](size_t i, size_t j) {
                        return sides[i].evaluate(centroids[j], nullptr) + sides[j].evaluate(centroids[i], nullptr) < 0;
                    };
                    MpuLocal candidate = local;
                    candidate.count = uint8_t(sides.size());
                    if (sides.size() == 2) {
                        candidate.combination = convex(0, 1) ? MpuCombination::Max : MpuCombination::Min;
                    } else {
                        const bool c01 = convex(0, 1), c02 = convex(0, 2), c12 = convex(1, 2);
                        const int convexPairs = int(c01) + int(c02) + int(c12);
                        if (convexPairs == 3) candidate.combination = MpuCombination::Max;
                        else if (convexPairs == 0) candidate.combination = MpuCombination::Min;
                        else {
                            // The odd pair goes first: (0, 1) in max(min(p0, p1), p2) or min(max(p0, p1), p2).
                            const bool oddIsConcave = convexPairs == 2;
                            const size_t other = (c12 != oddIsConcave) ? 0 : (c02 != oddIsConcave) ? 1 : 2;
                            std::swap(sides[other], sides[2]);
                            candidate.combination = oddIsConcave ? MpuCombination::MaxOfMin : MpuCombination::MinOfMax;
                        }
                    }
                    // Evaluate the candidate in place: its pieces go last for a moment.
                    const size_t mark = field.pieces_.size();
                    field.pieces_.insert(field.pieces_.end(), sides.begin(), sides.end());
                    const double sharpError =
                        ball.error([&](const Vec3& p, Vec3& g) { return field.evaluate(candidate, p, &g); });
                    field.pieces_.resize(mark);
                    if (sharpError < error) {
                        error = sharpError;
                        chosen = sides;
                        local = candidate;
                    }
                }
            }
        }
        if (fitted != &near && error <= tolerance) {
            // Judged on the subsample only so far: judge it on the whole ball.
            const size_t mark = field.pieces_.size();
            Local trial = local;
            trial.first = uint32_t(mark);
            field.pieces_.insert(field.pieces_.end(), chosen.begin(), chosen.end());
            error = BallFit::largestDistance(points, near, [&](const Vec3& p, Vec3& g) { return field.evaluate(trial, p, &g); });
            field.pieces_.resize(mark);
        }
        if (error > tolerance && !deepest) {
            for (int k = 0; k < 8; ++k) {
                const Vec3 offset((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5);
                stack.push_back({cell.center + cell.half * offset, 0.5 * cell.half, cell.depth + 1});
            }
            continue;
        }
        if (local.count == 1 && general) ++r.generalQuadrics;
        if (local.count == 2) ++r.edges;
        if (local.count == 3) ++r.corners;
        field.pieces_.insert(field.pieces_.end(), chosen.begin(), chosen.end());
        if (error > tolerance && radius > baseRadius) {
            // A ball that grew (its cell lies away from the data) and still
            // misses: growing by steps of 1.5 from a centre far from the
            // surface can take in a thousand points of a curved stretch no
            // quadric follows, and its weight would pull the blend off them.
            // Its support ends at the nearest point it misses by more than
            // kGrownBallMiss times the accuracy, but never inside the cell's
            // own ball, which keeps every point of the domain covered.
            double reach = radius;
            for (const uint32_t i : near) {
                Vec3 g;
                const double q = field.evaluate(local, points[i].position, &g);
                if (firstOrderDistance(q, g) > kGrownBallMiss * tolerance)
                    reach = std::min(reach, (points[i].position - cell.center).norm());
            }
            local.radius = std::max(baseRadius, reach);
        }
        field.locals_.push_back(local);
    }
    field.finish();

    // The fit's error: the blended field's first-order distance at the input.
    double errorSum = 0.0;
    for (const MpuPoint& p : points) {
        Vec3 g;
        const double value = field.valueAndGradient(p.position, g);
        const double error = firstOrderDistance(value, g) / diagonal;
        r.maxError = std::max(r.maxError, error);
        errorSum += error;
    }
    r.meanError = errorSum / double(points.size());
    r.localFunctions = field.locals_.size();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (report) *report = r;
    return field;
}

MpuField MpuField::fromParts(const Box3& domain, double support, double backgroundMargin, std::vector<MpuLocal> locals,
                             std::vector<MpuQuadric> pieces, std::vector<VariationalField> interpolants) {
    if (domain.isEmpty() || !domain.isFinite()) throw std::invalid_argument("the domain is empty or not finite");
    if (!(support > 0.5 && support <= 4)) throw std::invalid_argument("the support must lie in (0.5, 4]");
    if (!(backgroundMargin >= 0) || !std::isfinite(backgroundMargin))
        throw std::invalid_argument("the background margin must be finite and not negative");
    if (locals.empty()) throw std::invalid_argument("no local functions");
    for (size_t i = 0; i < locals.size(); ++i) {
        const MpuLocal& l = locals[i];
        const std::string which = "local function " + std::to_string(i);
        if (!l.center.allFinite() || !(l.radius > 0) || !std::isfinite(l.radius))
            throw std::invalid_argument(which + ": its ball is not finite");
        if (l.combination == MpuCombination::Interpolant) {
            if (l.count != 1 || l.first >= interpolants.size())
                throw std::invalid_argument(which + ": its interpolant is out of range");
            continue;
        }
        const bool countFits = l.combination == MpuCombination::Single ? l.count == 1
                               : (l.combination == MpuCombination::Max || l.combination == MpuCombination::Min)
                                   ? (l.count == 2 || l.count == 3)
                                   : l.count == 3;
        if (!countFits) throw std::invalid_argument(which + ": its combination does not fit its number of pieces");
        if (size_t(l.first) + l.count > pieces.size()) throw std::invalid_argument(which + ": its pieces are out of range");
    }
    for (size_t i = 0; i < pieces.size(); ++i) {
        const MpuQuadric& q = pieces[i];
        if (!q.origin.allFinite() || !q.A.allFinite() || !q.g.allFinite() || !std::isfinite(q.c0))
            throw std::invalid_argument("piece " + std::to_string(i) + " is not finite");
    }
    for (size_t i = 0; i < interpolants.size(); ++i) {
        const VariationalField& f = interpolants[i];
        bool finite = f.linear.allFinite() && std::isfinite(f.constant) && f.weights.size() == f.centers.size() &&
                      f.gradientWeights.size() == f.gradientCenters.size();
        for (size_t k = 0; finite && k < f.centers.size(); ++k) finite = f.centers[k].allFinite() && std::isfinite(f.weights[k]);
        for (size_t k = 0; finite && k < f.gradientCenters.size(); ++k)
            finite = f.gradientCenters[k].allFinite() && f.gradientWeights[k].allFinite();
        if (!finite) throw std::invalid_argument("interpolant " + std::to_string(i) + " is not finite or not whole");
    }
    MpuField field;
    field.domain_ = domain;
    field.support_ = support;
    field.backgroundMargin_ = backgroundMargin;
    field.locals_ = std::move(locals);
    field.pieces_ = std::move(pieces);
    field.interpolants_ = std::move(interpolants);
    field.finish();
    return field;
}

int MpuField::gridIndex(double coordinate, int axis) const {
    // Clamped as a double first: far points (or NaN) must not overflow an int.
    const double cell = std::floor((coordinate - domain_.lower[axis]) / cellSize_[axis]);
    return cell >= 0 ? int(std::min(cell, double(grid_ - 1))) : 0;
}

void MpuField::finish() {
    static std::atomic<uint64_t> nextId{1};
    id_ = nextId++;
    // Which locals reach each cell of a grid over the domain: exactly (for
    // evaluation and box queries) and within a margin of it (for the small
    // boxes of safe distances, answered from one cell's list).
    grid_ = std::clamp(int(std::cbrt(double(locals_.size()))) * 2, 4, 64);
    cellSize_ = domain_.extent() / grid_;
    nearMargin_ = 0.5 * cellSize_.minCoeff();
    const size_t cells = size_t(grid_) * grid_ * grid_;
    auto index = [&](double margin, std::vector<uint32_t>& start, std::vector<uint32_t>& items) {
        // The cells each ball reaches (the cell grown by the margin), axis
        // by axis: the squared gap from the centre to the cell's slab along
        // each axis, summed, against R^2 (raised a hair for rounding: a
        // local listed once too often costs nothing, one missing would).
        auto forCellsOf = [&](const Local& l, auto&& visit) {
            int lo[3], hi[3];
            for (int k = 0; k < 3; ++k) {
                lo[k] = gridIndex(l.center[k] - l.radius - margin, k);
                hi[k] = gridIndex(l.center[k] + l.radius + margin, k);
            }
            const double reach = l.radius * l.radius * (1 + 1e-12);
            auto gap = [&](int k, int c) {
                const double a = domain_.lower[k] + cellSize_[k] * c - margin,
                             b = domain_.lower[k] + cellSize_[k] * (c + 1) + margin;
                const double d = std::max({a - l.center[k], 0.0, l.center[k] - b});
                return d * d;
            };
            for (int x = lo[0]; x <= hi[0]; ++x) {
                const double gx = gap(0, x);
                if (!(gx < reach)) continue;
                for (int y = lo[1]; y <= hi[1]; ++y) {
                    const double gxy = gx + gap(1, y);
                    if (!(gxy < reach)) continue;
                    for (int z = lo[2]; z <= hi[2]; ++z)
                        if (gxy + gap(2, z) < reach) visit((size_t(x) * grid_ + y) * grid_ + z);
                }
            }
        };
        // Counted, then placed: no list per cell.
        start.assign(cells + 1, 0);
        for (const Local& l : locals_) forCellsOf(l, [&](size_t cell) { ++start[cell + 1]; });
        for (size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
        items.resize(start[cells]);
        std::vector<uint32_t> next(start.begin(), start.end() - 1);
        for (uint32_t i = 0; i < locals_.size(); ++i) forCellsOf(locals_[i], [&](size_t cell) { items[next[cell]++] = i; });
    };
    index(0.0, cellStart_, cellItems_);
    index(nearMargin_, nearStart_, nearItems_);
    // Rows for the vectorized sums, each quadric about its ball's centre
    // (MpuSumRows).
    auto rows = std::make_shared<MpuSumRows>();
    auto addRow = [&](const Local& l, const MpuQuadric& q) {
        Vec3 g;
        const double c0 = q.evaluate(l.center, &g);
        double* row = rows->rows.emplace_back().values;
        row[CenterX] = l.center.x();
        row[CenterY] = l.center.y();
        row[CenterZ] = l.center.z();
        row[InverseRadius2] = 1.0 / (l.radius * l.radius);
        row[C0] = c0;
        row[Gx] = g.x();
        row[Gy] = g.y();
        row[Gz] = g.z();
        row[Axx] = q.A(0, 0);
        row[Axy] = q.A(0, 1);
        row[Axz] = q.A(0, 2);
        row[Ayy] = q.A(1, 1);
        row[Ayz] = q.A(1, 2);
        row[Azz] = q.A(2, 2);
    };
    static_assert(sizeof(MpuLaneRow) == kMpuLaneColumns * sizeof(double));
    for (const Local& l : locals_) {
        if (l.combination == MpuCombination::Single) addRow(l, pieces_[l.first]);
        else rows->rows.emplace_back();  // a zero row keeps rows indexed by local
    }
    rows->sharpPieceRows.assign(locals_.size(), 0);
    for (size_t i = 0; i < locals_.size(); ++i) {
        const Local& l = locals_[i];
        if (l.combination == MpuCombination::Single || l.combination == MpuCombination::Interpolant) continue;
        rows->sharpPieceRows[i] = uint32_t(rows->rows.size());
        for (int k = 0; k < l.count; ++k) addRow(l, pieces_[l.first + k]);
    }
    sumRows_ = std::move(rows);
    // Each piece's |A| (Frobenius, at least the spectral norm, slightly
    // raised for rounding): its gradient g + 2 A y moves at most 2 |A| |dy|.
    pieceCurvatures_.resize(pieces_.size());
    for (size_t i = 0; i < pieces_.size(); ++i) pieceCurvatures_[i] = pieces_[i].A.norm() * (1 + 1e-12) + 1e-300;
    // An interpolant's evaluation sums its centres: the typical cost counts those.
    size_t centres = 0;
    for (const VariationalField& f : interpolants_) centres += f.termCount();
    const size_t perLocal = interpolants_.empty() ? 1 : std::max<size_t>(1, centres / interpolants_.size());
    typicalTerms_ = std::max<size_t>(1, cellItems_.size() / cells) * perLocal;
    // Every point of the domain lies in a leaf cell, at most half its
    // diagonal from the centre, and that cell's ball has a radius of at
    // least `support` diagonals: its weight there is at least this.
    const double t = 1.0 / (2.0 * support_);
    minimumWeight_ = std::pow(1.0 - t * t, 3);
}

// Points and boxes beyond the domain look up the grid cells they clamp to:
// clamping onto the domain (convex, holding every ball's centre) brings no
// point farther from a centre, so every ball reaching them reaches there too.
template <class Visit>
void MpuField::forLocalsAt(const Vec3& p, Visit&& visit) const {
    int c[3];
    for (int k = 0; k < 3; ++k) c[k] = gridIndex(p[k], k);
    const size_t cell = (size_t(c[0]) * grid_ + c[1]) * grid_ + c[2];
    for (uint32_t k = cellStart_[cell]; k < cellStart_[cell + 1]; ++k) visit(locals_[cellItems_[k]]);
}

template <class Visit>
void MpuField::forLocalsTouching(const Box3& box, Visit&& visit) const {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = gridIndex(box.lower[k], k);
        hi[k] = gridIndex(box.upper[k], k);
    }
    // A local is listed in every grid cell its ball reaches: visit it once
    // (a per-thread stamp per local, no allocation after the first call).
    thread_local std::vector<uint32_t> stamps;
    thread_local uint32_t stamp = 0;
    if (stamps.size() < locals_.size()) stamps.assign(locals_.size(), 0), stamp = 0;
    if (++stamp == 0) std::fill(stamps.begin(), stamps.end(), 0), stamp = 1;
    for (int x = lo[0]; x <= hi[0]; ++x)
        for (int y = lo[1]; y <= hi[1]; ++y)
            for (int z = lo[2]; z <= hi[2]; ++z) {
                const size_t cell = (size_t(x) * grid_ + y) * grid_ + z;
                for (uint32_t k = cellStart_[cell]; k < cellStart_[cell + 1]; ++k) {
                    const uint32_t i = cellItems_[k];
                    if (stamps[i] == stamp) continue;
                    stamps[i] = stamp;
                    const Local& l = locals_[i];
                    const Interval distance = box.distanceRange(l.center);
                    if (distance.lo < l.radius) visit(l, distance);
                }
            }
}

void MpuField::localsTouching(const Box3& box, std::vector<uint32_t>& out) const {
    out.clear();
    forLocalsTouching(box, [&](const Local& l, const Interval&) { out.push_back(uint32_t(&l - locals_.data())); });
}

MpuLocalList MpuField::singlesFirst(std::span<uint32_t> list) const {
    const auto end = std::stable_partition(list.begin(), list.end(), [&](uint32_t i) {
        return locals_[i].combination == MpuCombination::Single;
    });
    return {list, size_t(end - list.begin())};
}

double MpuField::value(const Vec3& p) const {
    Vec3 unused;
    return valueAndGradient(p, unused);
}

// A faint background term keeps f defined and continuous everywhere,
// beyond the balls too: weight kBackgroundWeight, value the distance to the
// domain plus a small positive margin (positive wherever the data is not).
double MpuField::background(const Vec3& p, Vec3* gradient) const {
    const Vec3 nearest = p.cwiseMax(domain_.lower).cwiseMin(domain_.upper), away = p - nearest;
    const double d = away.norm();
    if (gradient) *gradient = d > 0 ? Vec3(away / d) : Vec3(Vec3::Zero());
    return d + backgroundMargin_;
}

template <class ForLocals>
MpuBlendSums MpuField::sums(const Vec3& p, ForLocals&& forLocals) const {
    Vec3 gb;
    const double b = background(p, &gb);
    MpuBlendSums s;
    s.W = kBackgroundWeight;
    s.N = kBackgroundWeight * b;
    s.gradientW = Vec3::Zero();
    s.gradientN = kBackgroundWeight * gb;
    forLocals([&](const Local& l, int piece) {
        const Vec3 r = p - l.center;
        const double r2 = r.squaredNorm(), R2 = l.radius * l.radius;
        if (r2 >= R2) return;
        const double sigma = 1.0 - r2 / R2, w = sigma * sigma * sigma;
        const Vec3 dw = (-6.0 * sigma * sigma / R2) * r;
        Vec3 gq;
        const double q = evaluate(l, piece, p, &gq);
        s.W += w;
        s.N += w * q;
        s.gradientW += dw;
        s.gradientN += dw * q + w * gq;
    });
    return s;
}

template <class ForLocals>
double MpuField::blend(const Vec3& p, Vec3& gradient, ForLocals&& forLocals) const {
    const MpuBlendSums s = sums(p, forLocals);
    gradient = s.gradient();
    return s.value();
}

double MpuField::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    return blend(p, gradient, [&](auto&& visit) { forLocalsAt(p, [&](const Local& l) { visit(l, -1); }); });
}

double MpuField::valueAndGradient(const Vec3& p, Vec3& gradient, std::span<const uint32_t> locals) const {
    return blend(p, gradient, [&](auto&& visit) {
        for (const uint32_t i : locals) visit(locals_[i], -1);
    });
}

// Lists of up to this many locals take their resolved sharp locals in the
// vectorized sums (the rows are gathered on the stack); longer ones sum them
// one by one.
constexpr size_t kRowListCapacity = 256;

template <class OnRows, class VisitRest>
void MpuField::forRowsOf(MpuLocalList locals, OnRows&& onRows, VisitRest&& visitRest) const {
    const std::span<const uint32_t> singles = locals.singleLocals(), others = locals.otherLocals();
    if (locals.indices.size() > kRowListCapacity) {
        onRows(singles);
        for (size_t k = 0; k < others.size(); ++k) visitRest(locals_[others[k]], locals.pieceOf(k));
        return;
    }
    uint32_t rows[kRowListCapacity];
    std::copy(singles.begin(), singles.end(), rows);
    size_t count = singles.size();
    for (size_t k = 0; k < others.size(); ++k) {
        const int piece = locals.pieceOf(k);
        if (piece >= 0) rows[count++] = sumRows_->sharpPieceRows[others[k]] + uint32_t(piece);
        else visitRest(locals_[others[k]], -1);
    }
    onRows(std::span<const uint32_t>(rows, count));
}

double MpuField::numerator(const Vec3& p, MpuLocalList locals) const {
    double N = kBackgroundWeight * background(p, nullptr);
    forRowsOf(
        locals, [&](std::span<const uint32_t> rows) { N += onePieceNumerator(p, rows); },
        [&](const Local& l, int piece) {
            const double w = mpuWeight((p - l.center).squaredNorm(), l.radius * l.radius);
            if (w > 0.0) N += w * evaluate(l, piece, p, nullptr);
        });
    return N;
}

MpuBlendSums MpuField::blendSums(const Vec3& p, MpuLocalList locals) const {
    // The lanes' share is summed apart and added last.
    MpuBlendSums lanes;
    MpuBlendSums s = sums(p, [&](auto&& visit) {
        forRowsOf(locals, [&](std::span<const uint32_t> rows) { addOnePieceSums(p, rows, lanes); }, visit);
    });
    s.N += lanes.N;
    s.W += lanes.W;
    s.gradientN += lanes.gradientN;
    s.gradientW += lanes.gradientW;
    return s;
}

double MpuField::valueAndSafeDistance(const Vec3& p, double& safeDistance) const {
    // f = N / W with W > 0: f and the weighted sum N = sum w_i Q_i (plus the
    // background's term) have the same zeros, and N's slope is bounded term
    // by term, each local by its own |Q_i| and |grad Q_i|:
    //   |grad N| <= sum_i (|grad w_i| |Q_i| + w_i |grad Q_i|) + background.
    // Unlike f's bound, no local's poor fit far from its points (a ball
    // grown over sparse data) inflates the bound of every other one.
    //
    // Over the ball of radius h around p (h = |f| at most: near the surface
    // f is about a distance), each piece's gradient moves at most 2 |A| h
    // from its value at p (an interpolant's at most ||D^2|| h plus
    // ||D^3|| h^2 / 2), and its value at most that slope times h; w_i
    // and |grad w_i| come from the range of distances [d_i - h, d_i + h].
    // The bound proves the ball of radius |N| / L, and no more than h.
    //
    // Which balls can reach within h of p: when the h-ball lies inside p's
    // grid cell, those of the cell's own list (the common case near the
    // surface, where steps are short); otherwise those of its near list,
    // with h at most the near margin.
    struct Seen {
        double value, distance, radius, gradient, curvature;
        double third;  ///< an interpolant's third-derivative bound (0 for quadrics)
    };
    thread_local std::vector<Seen> seen;  // grows once per thread, then reused
    int c[3];
    double toFace = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
        c[k] = gridIndex(p[k], k);
        const double lower = domain_.lower[k] + c[k] * cellSize_[k];
        toFace = std::min({toFace, p[k] - lower, lower + cellSize_[k] - p[k]});
    }
    toFace = std::max(toFace, 0.0);  // beyond the domain: no room in the cell
    const size_t cell = (size_t(c[0]) * grid_ + c[1]) * grid_ + c[2];
    double W = 0.0, N = 0.0;
    auto gather = [&](const std::vector<uint32_t>& start, const std::vector<uint32_t>& items, double reach) {
        seen.clear();
        W = kBackgroundWeight;
        N = kBackgroundWeight * background(p, nullptr);
        for (uint32_t k = start[cell]; k < start[cell + 1]; ++k) {
            const Local& l = locals_[items[k]];
            const double r2 = (p - l.center).squaredNorm(), R = l.radius, R2 = R * R;
            if (r2 >= (R + reach) * (R + reach)) continue;
            double value = 0.0, gradient = 0.0, curvature = 0.0, third = 0.0;
            if (l.combination == MpuCombination::Interpolant) {
                // Its gradient over the h-ball: |grad| + ||D^2|| h + ||D^3|| h^2 / 2.
                const VariationalField::PointBounds b = interpolants_[l.first].boundsAt(p);
                value = b.value;
                gradient = b.gradientNorm;
                curvature = 0.5 * b.hessian;
                third = b.third;
            } else {
                // Each piece's value and gradient at p; a max or min of pieces
                // takes one of their values (and gradients).
                const MpuQuadric* q = &pieces_[l.first];
                double v[3] = {0.0, 0.0, 0.0};
                for (int i = 0; i < l.count; ++i) {
                    Vec3 g;
                    v[i] = q[i].evaluate(p, &g);
                    gradient = std::max(gradient, g.norm());
                    curvature = std::max(curvature, pieceCurvatures_[l.first + i]);
                }
                value = combineMpuPieces(l, v, largerValue, smallerValue);
            }
            seen.push_back({value, std::sqrt(r2), R, gradient, curvature, third});
            if (r2 >= R2) continue;
            const double s = 1.0 - r2 / R2, w = s * s * s;
            W += w;
            N += w * value;
        }
    };
    gather(cellStart_, cellItems_, toFace);
    const double v = N / W;
    safeDistance = 0.0;
    if (!(std::abs(N) > 0)) return v;
    double h = std::abs(v);
    if (h > toFace) {
        // The h-ball leaves the cell: the near list holds every ball within
        // the margin of it (N and W come out the same, summed again).
        h = std::min(h, nearMargin_);
        gather(nearStart_, nearItems_, h);
    }
    double slope = kBackgroundWeight;  // |grad b| <= 1
    for (const Seen& l : seen) {
        const Interval distance{std::max(0.0, l.distance - h), l.distance + h};
        if (distance.lo >= l.radius) continue;
        const double gradient = l.gradient + 2.0 * l.curvature * h + 0.5 * l.third * h * h;
        slope += mpuWeightSlope(distance, l.radius) * (std::abs(l.value) + gradient * h) +
                 mpuWeight(distance.lo * distance.lo, l.radius * l.radius) * gradient;
    }
    safeDistance = std::min(h, std::abs(N) / (slope * (1 + 1e-9)));
    return v;
}

Interval MpuField::range(const Box3& box) const {
    // f is a convex combination of the background and the locals reaching the box.
    const Vec3 lo = box.lower.cwiseMax(domain_.lower).cwiseMin(domain_.upper);
    const Vec3 hi = box.upper.cwiseMax(domain_.lower).cwiseMin(domain_.upper);
    const double farthest = (box.lower - lo).cwiseAbs().cwiseMax((box.upper - hi).cwiseAbs()).norm();
    Interval hull{backgroundMargin_, backgroundMargin_ + farthest + 1e-12};
    // The background's smallest value over the box is its margin plus the
    // box's distance to the domain, at least the margin: the hull above is sound.
    // f = N / W has the sign of N = sum w_i Q_i: where N's range keeps one
    // sign, so does f, and |f| >= |N| / W.hi. A local fitted poorly far
    // from its points widens the hull but weighs little where it does.
    Interval weighted = kBackgroundWeight * hull, weights{kBackgroundWeight, kBackgroundWeight};
    double magnitude = std::abs(weighted.lo) + std::abs(weighted.hi);
    forLocalsTouching(box, [&](const Local& l, const Interval& distance) {
        const Interval q = range(l, box);
        hull = {std::min(hull.lo, q.lo), std::max(hull.hi, q.hi)};
        const double R2 = l.radius * l.radius;
        const Interval w{mpuWeight(distance.hi * distance.hi, R2), mpuWeight(distance.lo * distance.lo, R2)};
        const Interval term = w * q;
        weighted += term;
        weights += w;
        magnitude += std::abs(term.lo) + std::abs(term.hi);
    });
    const double slack = 1e-12 * magnitude;  // rounding of the sums
    if (weighted.lo - slack > 0) hull.lo = std::max(hull.lo, (weighted.lo - slack) / (weights.hi * (1 + 1e-12)));
    if (weighted.hi + slack < 0) hull.hi = std::min(hull.hi, (weighted.hi + slack) / (weights.hi * (1 + 1e-12)));
    return hull;
}

double MpuField::lipschitz(const Box3& box) const {
    const double farthest = (box.lower - box.lower.cwiseMax(domain_.lower).cwiseMin(domain_.upper))
                                .cwiseAbs()
                                .cwiseMax((box.upper - box.upper.cwiseMax(domain_.lower).cwiseMin(domain_.upper)).cwiseAbs())
                                .norm();
    Interval hull{backgroundMargin_, backgroundMargin_ + farthest + 1e-12};
    double gradientQ = 1.0;  // the background's slope
    double slopes = 0.0, weightBelow = kBackgroundWeight;
    forLocalsTouching(box, [&](const Local& l, const Interval& distance) {
        const Interval q = range(l, box);
        hull = {std::min(hull.lo, q.lo), std::max(hull.hi, q.hi)};
        gradientQ = std::max(gradientQ, gradientBound(l, box));
        const double R = l.radius;
        slopes += mpuWeightSlope(distance, R);
        // Its weight is at least its value at the farthest point of the box.
        if (distance.hi < R) weightBelow += mpuWeight(distance.hi * distance.hi, R * R);
    });
    // Inside the domain every point lies in a cell whose ball reaches it,
    // which bounds W from below; elsewhere only the weights' minima do.
    const bool inside = (box.lower.array() >= domain_.lower.array()).all() && (box.upper.array() <= domain_.upper.array()).all();
    const double weight = inside ? std::max(minimumWeight_, weightBelow) : weightBelow;
    return (gradientQ + (hull.hi - hull.lo) * slopes / weight) * (1 + 1e-9);
}

}  // namespace isotrace::geometry
