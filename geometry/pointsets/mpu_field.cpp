// An MPU field once fitted (mpu_fit.cpp fits it): its local functions and
// their grid, evaluation of the blend and its sums, and proven ranges,
// Lipschitz bounds and safe distances. docs/design/mpu.md says why.
#include "geometry/pointsets/mpu_field.h"
#include "geometry/pointsets/mpu_lane_kernels.h"
#include "geometry/pointsets/mpu_numerator_model.h"

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>


namespace isotrace::geometry {


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

double evaluateMpuPieces(const MpuLocal& l, const MpuQuadric* q, const Vec3& x, Vec3* gradient) {
    if (l.combination == MpuCombination::Single) return q[0].evaluate(x, gradient);
    PieceValue v[3]{};
    for (int k = 0; k < l.count; ++k) v[k].value = q[k].evaluate(x, &v[k].gradient);
    const PieceValue r = combineMpuPieces(l, v, larger, smaller);
    if (gradient) *gradient = r.gradient;
    return r.value;
}

double MpuField::evaluate(const Local& l, const Vec3& x, Vec3* gradient) const {
    if (l.combination == MpuCombination::Interpolant) {
        const VariationalField& f = interpolants_[l.first];
        if (!gradient) return f.value(x);
        return f.valueAndGradient(x, *gradient);
    }
    return evaluateMpuPieces(l, &pieces_[l.first], x, gradient);
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
