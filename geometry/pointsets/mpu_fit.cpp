// Fitting an MPU field to oriented points (Ohtake et al. 2003): an octree
// over the points whose cells each fit a local function to the points in a
// ball around them, divided until the fit meets the accuracy. The field's
// evaluation and bounds are in mpu_field.cpp; docs/design/mpu.md says why.
#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "geometry/point_grid.h"
#include "geometry/pointsets/mpu_field.h"

namespace isotrace::geometry {

namespace {

void orthonormalFrame(const Vec3& n, Vec3& u, Vec3& v) {
    u = n.unitOrthogonal();
    v = n.cross(u);
}

// |value| / |gradient|: a point's first-order distance to the zero set,
// how fits are judged at their points.
double firstOrderDistance(double value, const Vec3& gradient) {
    return std::abs(value) / std::max(gradient.norm(), 1e-300);
}

// Balls holding more points fit their functions to an even subsample of this many.
constexpr size_t kMaxBallFitPoints = 4096;

// A grown ball's support ends at the nearest point its function misses by
// more than this many times the accuracy. Near thin parts of sparse data a
// local that misses by a little is still the best there is; trimming
// tighter or not at all leaves the worst point farther (bench/RESULTS.md,
// "Tuned constants").
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

// A cell's local function and its error at the points it was fitted to.
struct LocalFit {
    MpuLocal local;  ///< `first` still to be set where its pieces are stored
    std::vector<MpuQuadric> pieces;
    double error = 0.0;
    bool general = false;  ///< one general quadric, where the normals disagree
};

// Where a smooth function misses, an edge or corner may be the cause: one
// height function per cluster of normals, joined by max where the edge is
// convex (each side's centroid inside the other's function) and by min
// where it is concave. Returns the candidate, or nothing where the normals
// do not fall into clusters.
std::optional<LocalFit> fitSharpFeature(const BallFit& ball, const Vec3& meanNormal, const MpuLocal& smooth) {
    const std::vector<std::vector<uint32_t>> clusters = ball.normalClusters(meanNormal);
    if (clusters.size() < 2) return std::nullopt;
    std::vector<MpuQuadric> sides;
    std::vector<Vec3> centroids;
    for (const std::vector<uint32_t>& c : clusters) {
        Vec3 cc, cn;
        if (!ball.moments(c, cc, cn)) return std::nullopt;
        sides.push_back(ball.heightFunction(c, cc, cn));
        centroids.push_back(cc);
    }
    auto convex = [&](size_t i, size_t j) {
        return sides[i].evaluate(centroids[j], nullptr) + sides[j].evaluate(centroids[i], nullptr) < 0;
    };
    LocalFit candidate;
    candidate.local = smooth;
    candidate.local.count = uint8_t(sides.size());
    if (sides.size() == 2) {
        candidate.local.combination = convex(0, 1) ? MpuCombination::Max : MpuCombination::Min;
    } else {
        const bool c01 = convex(0, 1), c02 = convex(0, 2), c12 = convex(1, 2);
        const int convexPairs = int(c01) + int(c02) + int(c12);
        if (convexPairs == 3) candidate.local.combination = MpuCombination::Max;
        else if (convexPairs == 0) candidate.local.combination = MpuCombination::Min;
        else {
            // The odd pair goes first: (0, 1) in max(min(p0, p1), p2) or min(max(p0, p1), p2).
            const bool oddIsConcave = convexPairs == 2;
            const size_t other = (c12 != oddIsConcave) ? 0 : (c02 != oddIsConcave) ? 1 : 2;
            std::swap(sides[other], sides[2]);
            candidate.local.combination = oddIsConcave ? MpuCombination::MaxOfMin : MpuCombination::MinOfMax;
        }
    }
    candidate.pieces = std::move(sides);
    candidate.error = ball.error([&](const Vec3& p, Vec3& g) {
        return evaluateMpuPieces(candidate.local, candidate.pieces.data(), p, &g);
    });
    return candidate;
}

// The best local function for a ball: a height function where the normals
// agree, a general quadric where they do not, and with sharp features an
// edge or corner function where that misses less than the smooth one.
LocalFit fitBall(const BallFit& ball, const std::vector<MpuPoint>& points, const std::vector<uint32_t>& fitted,
                 const Vec3& center, double radius, double tolerance, bool sharpFeatures) {
    std::vector<uint32_t> all(fitted.size());
    for (size_t k = 0; k < all.size(); ++k) all[k] = uint32_t(k);
    Vec3 centroid, normal;
    const bool normalsAgree = ball.moments(all, centroid, normal);
    double agreement = normalsAgree ? 1.0 : -1.0;
    for (uint32_t i : fitted) agreement = std::min(agreement, points[i].normal.normalized().dot(normal));
    LocalFit best;
    best.general = agreement < 0.2;
    const MpuQuadric smooth = best.general ? ball.generalQuadric(centroid) : ball.heightFunction(all, centroid, normal);
    best.error = ball.error([&](const Vec3& p, Vec3& g) { return smooth.evaluate(p, &g); });
    best.local.center = center;
    best.local.radius = radius;
    best.pieces = {smooth};
    if (best.error > tolerance && sharpFeatures) {
        std::optional<LocalFit> sharp = fitSharpFeature(ball, normal, best.local);
        if (sharp && sharp->error < best.error) {
            sharp->general = best.general;
            best = std::move(*sharp);
        }
    }
    return best;
}

// The radius a grown ball keeps: a ball that grew (its cell lies away from
// the data) and still misses can, growing by steps of 1.5 from a centre far
// from the surface, take in a thousand points of a curved stretch no
// quadric follows, and its weight would pull the blend off them. Its
// support ends at the nearest point it misses by more than kGrownBallMiss
// times the accuracy, but never inside the cell's own ball, which keeps
// every point of the domain covered.
double trimmedRadius(const LocalFit& fit, const std::vector<MpuPoint>& points, const std::vector<uint32_t>& near,
                     double baseRadius, double tolerance) {
    double reach = fit.local.radius;
    for (const uint32_t i : near) {
        Vec3 g;
        const double q = evaluateMpuPieces(fit.local, fit.pieces.data(), points[i].position, &g);
        if (firstOrderDistance(q, g) > kGrownBallMiss * tolerance)
            reach = std::min(reach, (points[i].position - fit.local.center).norm());
    }
    return std::max(baseRadius, reach);
}

// The points' bounding box, after checking the options and the points.
Box3 checkedPointBox(const std::vector<MpuPoint>& points, const MpuOptions& options) {
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
    if (!(box.extent().norm() > 0)) throw std::invalid_argument("all points coincide");
    return box;
}

}  // namespace

MpuField MpuField::fit(const std::vector<MpuPoint>& points, const MpuOptions& options, MpuReport* report) {
    const auto start = std::chrono::steady_clock::now();
    const Box3 box = checkedPointBox(points, options);
    const double diagonal = box.extent().norm();
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
        // accuracy at every point of the ball.
        const std::vector<uint32_t>* fitted = &near;
        if (near.size() > kMaxBallFitPoints) {
            sample.clear();
            const double stride = double(near.size()) / double(kMaxBallFitPoints);
            for (size_t k = 0; k < kMaxBallFitPoints; ++k) sample.push_back(near[size_t(double(k) * stride)]);
            fitted = &sample;
        }
        const BallFit ball(points, *fitted, cell.center, radius);
        LocalFit fit = fitBall(ball, points, *fitted, cell.center, radius, tolerance, options.sharpFeatures);
        if (fitted != &near && fit.error <= tolerance) {
            // Judged on the subsample only so far: judge it on the whole ball.
            fit.error = BallFit::largestDistance(points, near, [&](const Vec3& p, Vec3& g) {
                return evaluateMpuPieces(fit.local, fit.pieces.data(), p, &g);
            });
        }
        if (fit.error > tolerance && !deepest) {
            for (int k = 0; k < 8; ++k) {
                const Vec3 offset((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5);
                stack.push_back({cell.center + cell.half * offset, 0.5 * cell.half, cell.depth + 1});
            }
            continue;
        }
        if (fit.local.count == 1 && fit.general) ++r.generalQuadrics;
        if (fit.local.count == 2) ++r.edges;
        if (fit.local.count == 3) ++r.corners;
        if (fit.error > tolerance && radius > baseRadius)
            fit.local.radius = trimmedRadius(fit, points, near, baseRadius, tolerance);
        fit.local.first = uint32_t(field.pieces_.size());
        field.pieces_.insert(field.pieces_.end(), fit.pieces.begin(), fit.pieces.end());
        field.locals_.push_back(fit.local);
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

}  // namespace isotrace::geometry
