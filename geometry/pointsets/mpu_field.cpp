#include "geometry/pointsets/mpu_field.h"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace isotrace::geometry {

namespace {

double weightOf(double r2, double radius2) {
    if (r2 >= radius2) return 0.0;
    const double s = 1.0 - r2 / radius2;
    return s * s * s;
}

// Largest |d/dr (1 - r^2/R^2)^3| is 6 t (1 - t^2)^2 / R at t = 1/sqrt 5.
constexpr double kWeightSlope = 1.7173285067805897;

void orthonormalFrame(const Vec3& n, Vec3& u, Vec3& v) {
    u = n.unitOrthogonal();
    v = n.cross(u);
}

// Point queries over the input: cells of a uniform grid.
class PointIndex {
public:
    PointIndex(const std::vector<MpuPoint>& points, const Box3& box, int resolution)
        : points_(points), box_(box), resolution_(resolution) {
        cell_ = box.extent() / resolution;
        start_.assign(size_t(resolution) * resolution * resolution + 1, 0);
        std::vector<uint32_t> cellOf(points.size());
        for (size_t i = 0; i < points.size(); ++i) ++start_[(cellOf[i] = index(points[i].position)) + 1];
        for (size_t k = 1; k < start_.size(); ++k) start_[k] += start_[k - 1];
        items_.resize(points.size());
        std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
        for (size_t i = 0; i < points.size(); ++i) items_[fill[cellOf[i]]++] = uint32_t(i);
    }
    /// Indices of the points within `radius` of `center`.
    void within(const Vec3& center, double radius, std::vector<uint32_t>& out) const {
        out.clear();
        int lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::clamp(int(std::floor((center[k] - radius - box_.lower[k]) / cell_[k])), 0, resolution_ - 1);
            hi[k] = std::clamp(int(std::floor((center[k] + radius - box_.lower[k]) / cell_[k])), 0, resolution_ - 1);
        }
        const double r2 = radius * radius;
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    const size_t c = (size_t(x) * resolution_ + y) * resolution_ + z;
                    for (uint32_t k = start_[c]; k < start_[c + 1]; ++k)
                        if ((points_[items_[k]].position - center).squaredNorm() < r2) out.push_back(items_[k]);
                }
    }

private:
    uint32_t index(const Vec3& p) const {
        int c[3];
        for (int k = 0; k < 3; ++k) c[k] = std::clamp(int(std::floor((p[k] - box_.lower[k]) / cell_[k])), 0, resolution_ - 1);
        return uint32_t((size_t(c[0]) * resolution_ + c[1]) * resolution_ + c[2]);
    }
    const std::vector<MpuPoint>& points_;
    Box3 box_;
    int resolution_;
    Vec3 cell_;
    std::vector<uint32_t> start_, items_;
};

}  // namespace

double MpuField::Local::evaluate(const Vec3& x, Vec3* gradient) const {
    const Vec3 y = x - origin;
    const Vec3 Ay = A * y;
    if (gradient) *gradient = g + 2.0 * Ay;
    return c0 + g.dot(y) + y.dot(Ay);
}

namespace {
Interval square(Interval a) {
    const double lo2 = a.lo * a.lo, hi2 = a.hi * a.hi;
    if (a.lo <= 0 && a.hi >= 0) return {0.0, std::max(lo2, hi2)};
    return {std::min(lo2, hi2), std::max(lo2, hi2)};
}
}  // namespace

Interval MpuField::Local::range(const Box3& box) const {
    Interval y[3];
    for (int k = 0; k < 3; ++k) y[k] = {box.lower[k] - origin[k], box.upper[k] - origin[k]};
    Interval q{c0, c0};
    for (int k = 0; k < 3; ++k) {
        q += g[k] * y[k];
        q += A(k, k) * square(y[k]);
        for (int l = k + 1; l < 3; ++l) q += (2.0 * A(k, l)) * (y[k] * y[l]);
    }
    return widened(q);
}

double MpuField::Local::gradientBound(const Box3& box) const {
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
    // The root cube: the points' box, centred, 30% wider, so the surface stays inside.
    const double half = 0.65 * box.extent().maxCoeff();
    field.domain_ = Box3::around(box.center(), half);
    const PointIndex index(points, field.domain_, 48);
    MpuReport r;
    std::vector<uint32_t> near;

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
        auto subdivide = [&] {
            for (int k = 0; k < 8; ++k) {
                const Vec3 offset((k & 1) ? 0.5 : -0.5, (k & 2) ? 0.5 : -0.5, (k & 4) ? 0.5 : -0.5);
                stack.push_back({cell.center + cell.half * offset, 0.5 * cell.half, cell.depth + 1});
            }
        };
        // Weighted centroid and mean normal of the ball.
        Local local;
        local.center = cell.center;
        local.radius = radius;
        const double radius2 = radius * radius;
        auto weightAt = [&](uint32_t i) {
            return std::max(weightOf((points[i].position - cell.center).squaredNorm(), radius2), 1e-12);
        };
        double total = 0;
        Vec3 centroid = Vec3::Zero(), normal = Vec3::Zero();
        for (uint32_t i : near) {
            const double w = weightAt(i);
            total += w;
            centroid += w * points[i].position;
            normal += w * points[i].normal.normalized();
        }
        centroid /= total;
        local.origin = centroid;
        const bool normalsCancel = !(normal.norm() > 1e-9 * total);
        if (!normalsCancel) normal.normalize();
        double agreement = normalsCancel ? -1.0 : 1.0;
        for (uint32_t i : near) agreement = std::min(agreement, points[i].normal.normalized().dot(normal));
        const double scale = 1.0 / radius;  // fits in conditioned coordinates
        if (agreement >= 0.2) {
            // A height function over the mean plane: h(s, t) = a s^2 + b s t + c t^2 + d s + e t + f.
            Vec3 u, v;
            orthonormalFrame(normal, u, v);
            Eigen::Matrix<double, 6, 6> M = Eigen::Matrix<double, 6, 6>::Zero();
            Eigen::Matrix<double, 6, 1> rhs = Eigen::Matrix<double, 6, 1>::Zero();
            for (uint32_t i : near) {
                const Vec3 q = (points[i].position - centroid) * scale;
                const double s = q.dot(u), t = q.dot(v), h = q.dot(normal), w = weightAt(i);
                Eigen::Matrix<double, 6, 1> row;
                row << s * s, s * t, t * t, s, t, 1.0;
                M += w * row * row.transpose();
                rhs += w * h * row;
            }
            M.diagonal().array() += 1e-9 * std::max(M.trace(), 1e-300);
            Eigen::Matrix<double, 6, 1> x = M.ldlt().solve(rhs);
            if (!x.allFinite()) x.setZero();
            // Q(y) = n.y - h(u.y, v.y) in world units: h = radius H(s/radius, t/radius).
            const double a = x[0] / radius, b = x[1] / radius, c = x[2] / radius;
            local.A = -(a * u * u.transpose() + 0.5 * b * (u * v.transpose() + v * u.transpose()) + c * v * v.transpose());
            local.g = normal - x[3] * u - x[4] * v;
            local.c0 = -x[5] * radius;
        } else {
            // A general quadric: zero at the points, +delta and -delta at
            // auxiliary points delta along and against their normals.
            ++r.generalQuadrics;
            Eigen::Matrix<double, 10, 10> M = Eigen::Matrix<double, 10, 10>::Zero();
            Eigen::Matrix<double, 10, 1> rhs = Eigen::Matrix<double, 10, 1>::Zero();
            const double delta = 0.1;  // in conditioned units: a tenth of the ball's radius
            for (uint32_t i : near) {
                const Vec3 q = (points[i].position - centroid) * scale, n = points[i].normal.normalized();
                const double w = weightAt(i);
                for (int side = -1; side <= 1; ++side) {
                    const Vec3 y = q + side * delta * n;
                    Eigen::Matrix<double, 10, 1> row;
                    row << y.x() * y.x(), y.y() * y.y(), y.z() * y.z(), 2 * y.x() * y.y(), 2 * y.x() * y.z(),
                        2 * y.y() * y.z(), y.x(), y.y(), y.z(), 1.0;
                    M += w * row * row.transpose();
                    rhs += w * (side * delta) * row;
                }
            }
            M.diagonal().array() += 1e-9 * std::max(M.trace(), 1e-300);
            Eigen::Matrix<double, 10, 1> x = M.ldlt().solve(rhs);
            if (!x.allFinite()) x.setZero();
            // Back to world units: Q(y) = radius Qc(y / radius).
            Mat3 A;
            A << x[0], x[3], x[4], x[3], x[1], x[5], x[4], x[5], x[2];
            local.A = A / radius;
            local.g = Vec3(x[6], x[7], x[8]);
            local.c0 = x[9] * radius;
        }
        double error = 0;
        for (uint32_t i : near) {
            Vec3 g;
            const double q = local.evaluate(points[i].position, &g);
            error = std::max(error, std::abs(q) / std::max(g.norm(), 1e-300));
        }
        if (error > tolerance && !deepest) {
            subdivide();
            continue;
        }
        field.locals_.push_back(local);
    }

    // Which locals reach each cell of a grid over the domain.
    field.grid_ = std::clamp(int(std::cbrt(double(field.locals_.size()))) * 2, 4, 64);
    field.cellSize_ = field.domain_.extent() / field.grid_;
    const size_t cells = size_t(field.grid_) * field.grid_ * field.grid_;
    std::vector<std::vector<uint32_t>> lists(cells);
    for (uint32_t i = 0; i < field.locals_.size(); ++i) {
        const Local& l = field.locals_[i];
        int lo[3], hi[3];
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::clamp(int(std::floor((l.center[k] - l.radius - field.domain_.lower[k]) / field.cellSize_[k])), 0, field.grid_ - 1);
            hi[k] = std::clamp(int(std::floor((l.center[k] + l.radius - field.domain_.lower[k]) / field.cellSize_[k])), 0, field.grid_ - 1);
        }
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    const Box3 c(field.domain_.lower + field.cellSize_.cwiseProduct(Vec3(x, y, z)),
                                 field.domain_.lower + field.cellSize_.cwiseProduct(Vec3(x + 1, y + 1, z + 1)));
                    if (c.distanceRange(l.center).lo < l.radius) lists[(size_t(x) * field.grid_ + y) * field.grid_ + z].push_back(i);
                }
    }
    field.cellStart_.assign(cells + 1, 0);
    size_t sum = 0;
    for (size_t c = 0; c < cells; ++c) {
        field.cellStart_[c + 1] = field.cellStart_[c] + uint32_t(lists[c].size());
        field.cellItems_.insert(field.cellItems_.end(), lists[c].begin(), lists[c].end());
        sum += lists[c].size();
    }
    field.typicalTerms_ = std::max<size_t>(1, sum / cells);
    // Every point of the domain lies in a leaf cell, at most half its
    // diagonal from the centre, and that cell's ball has a radius of at
    // least `support` diagonals: its weight there is at least this.
    const double t = 1.0 / (2.0 * options.support);
    field.minimumWeight_ = std::pow(1.0 - t * t, 3);
    field.backgroundMargin_ = 1e-3 * diagonal;

    // The fit's error: the blended field's first-order distance at the input.
    for (const MpuPoint& p : points) {
        Vec3 g;
        const double value = field.valueAndGradient(p.position, g);
        r.maxError = std::max(r.maxError, std::abs(value) / std::max(g.norm(), 1e-300) / diagonal);
    }
    r.localFunctions = field.locals_.size();
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (report) *report = r;
    return field;
}

template <class Visit>
void MpuField::forLocalsAt(const Vec3& p, Visit&& visit) const {
    if (!domain_.contains(p)) {  // the grid covers the domain only: ask every local
        for (const Local& l : locals_) visit(l);
        return;
    }
    int c[3];
    for (int k = 0; k < 3; ++k) c[k] = std::clamp(int(std::floor((p[k] - domain_.lower[k]) / cellSize_[k])), 0, grid_ - 1);
    const size_t cell = (size_t(c[0]) * grid_ + c[1]) * grid_ + c[2];
    for (uint32_t k = cellStart_[cell]; k < cellStart_[cell + 1]; ++k) visit(locals_[cellItems_[k]]);
}

template <class Visit>
void MpuField::forLocalsTouching(const Box3& box, Visit&& visit) const {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
        lo[k] = std::clamp(int(std::floor((box.lower[k] - domain_.lower[k]) / cellSize_[k])), 0, grid_ - 1);
        hi[k] = std::clamp(int(std::floor((box.upper[k] - domain_.lower[k]) / cellSize_[k])), 0, grid_ - 1);
    }
    // A local is listed in every grid cell its ball reaches: visit it once
    // (a per-thread stamp per local, no allocation after the first call).
    if (!(box.lower.array() >= domain_.lower.array()).all() || !(box.upper.array() <= domain_.upper.array()).all()) {
        for (const Local& l : locals_) {  // beyond the grid: ask every local
            const Interval distance = box.distanceRange(l.center);
            if (distance.lo < l.radius) visit(l, distance);
        }
        return;
    }
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

double MpuField::valueAndGradient(const Vec3& p, Vec3& gradient) const {
    Vec3 gb;
    const double b = background(p, &gb);
    double W = kBackgroundWeight, F = kBackgroundWeight * b;
    Vec3 dW = Vec3::Zero(), dF = kBackgroundWeight * gb;
    forLocalsAt(p, [&](const Local& l) {
        const Vec3 r = p - l.center;
        const double r2 = r.squaredNorm(), R2 = l.radius * l.radius;
        if (r2 >= R2) return;
        const double s = 1.0 - r2 / R2, w = s * s * s;
        const Vec3 dw = (-6.0 * s * s / R2) * r;
        Vec3 gq;
        const double q = l.evaluate(p, &gq);
        W += w;
        F += w * q;
        dW += dw;
        dF += dw * q + w * gq;
    });
    gradient = (dF * W - F * dW) / (W * W);
    return F / W;
}

Interval MpuField::range(const Box3& box) const {
    // f is a convex combination of the background and the locals reaching the box.
    const Vec3 lo = box.lower.cwiseMax(domain_.lower).cwiseMin(domain_.upper);
    const Vec3 hi = box.upper.cwiseMax(domain_.lower).cwiseMin(domain_.upper);
    const double farthest = (box.lower - lo).cwiseAbs().cwiseMax((box.upper - hi).cwiseAbs()).norm();
    Interval hull{backgroundMargin_, backgroundMargin_ + farthest + 1e-12};
    // The background's smallest value over the box is its margin plus the
    // box's distance to the domain, at least the margin: the hull above is sound.
    forLocalsTouching(box, [&](const Local& l, const Interval&) {
        const Interval q = l.range(box);
        hull = {std::min(hull.lo, q.lo), std::max(hull.hi, q.hi)};
    });
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
        const Interval q = l.range(box);
        hull = {std::min(hull.lo, q.lo), std::max(hull.hi, q.hi)};
        gradientQ = std::max(gradientQ, l.gradientBound(box));
        // |grad w| = 6 r (1 - r^2/R^2)^2 / R^2 rises up to r = R / sqrt 5
        // and falls after: its largest value over the box's distances.
        const double R = l.radius, peak = R / std::sqrt(5.0);
        const double a = distance.lo, b = std::min(distance.hi, R);
        auto slope = [&](double r) {
            const double s = 1.0 - r * r / (R * R);
            return 6.0 * r * s * s / (R * R);
        };
        slopes += b <= peak ? slope(b) : a >= peak ? slope(a) : kWeightSlope / R;
        // Its weight is at least its value at the farthest point of the box.
        if (distance.hi < R) weightBelow += weightOf(distance.hi * distance.hi, R * R);
    });
    // Inside the domain every point lies in a cell whose ball reaches it,
    // which bounds W from below; elsewhere only the weights' minima do.
    const bool inside = (box.lower.array() >= domain_.lower.array()).all() && (box.upper.array() <= domain_.upper.array()).all();
    const double weight = inside ? std::max(minimumWeight_, weightBelow) : weightBelow;
    return (gradientQ + (hull.hi - hull.lo) * slopes / weight) * (1 + 1e-9);
}

}  // namespace isotrace::geometry
