#include "geometry/pointsets/mpu_numerator_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {

// Which of a local's pieces its combination takes where they have the
// values v.
int pieceTaken(const MpuLocal& l, const double* v) {
    struct Valued {
        double value;
        int index;
    };
    const Valued at[3] = {{v[0], 0}, {l.count > 1 ? v[1] : 0.0, 1}, {l.count > 2 ? v[2] : 0.0, 2}};
    return combineMpuPieces(
               l, at, [](Valued a, Valued b) { return a.value >= b.value ? a : b; },
               [](Valued a, Valued b) { return a.value <= b.value ? a : b; })
        .index;
}

// The piece a local takes at the box's centre, and whether it takes it all
// over the box center +- half (false where its pieces cross there: a sharp
// local's crease).
struct PieceInEffect {
    int index = 0;
    bool throughout = true;
};
PieceInEffect pieceInEffect(const MpuField& field, const MpuLocal& l, const Vec3& center, const Vec3& half) {
    if (l.count == 1) return {};
    const MpuQuadric* q = &field.pieces()[l.first];
    double v[3];
    Vec3 g[3];
    for (int k = 0; k < l.count; ++k) v[k] = q[k].evaluate(center, &g[k]);
    int order[3][3] = {};  // +1 where piece i exceeds piece j all over the box, -1 where it is below
    for (int i = 0; i < l.count; ++i)
        for (int j = i + 1; j < l.count; ++j) {
            const Interval d = quadraticRange(v[i] - v[j], g[i] - g[j], q[i].A - q[j].A, half);
            order[i][j] = d.lo > 0 ? 1 : d.hi < 0 ? -1 : 0;
            order[j][i] = -order[i][j];
        }
    struct Choice {
        int index;  ///< -1: not known
    };
    auto pick = [&](Choice a, Choice b, int larger) {
        if (a.index < 0 || b.index < 0) return Choice{-1};
        const int o = order[a.index][b.index] * larger;
        return o > 0 ? a : o < 0 ? b : Choice{-1};
    };
    const Choice pieces[3] = {{0}, {1}, {2}};
    const int throughout = combineMpuPieces(
                               l, pieces, [&](Choice a, Choice b) { return pick(a, b, 1); },
                               [&](Choice a, Choice b) { return pick(a, b, -1); })
                               .index;
    if (throughout >= 0) return {throughout, true};
    return {pieceTaken(l, v), false};
}

// The largest |d^2/dtau^2 w(x + tau u)| over unit u and distances r from
// the ball's centre in `distance`. With v = r^2 / R^2 and sigma = 1 - v,
// w'' = 6 sigma s'^2 - 3 sigma^2 s'' where 0 <= s'^2 <= 4 v / R^2 and
// s'' = 2 / R^2, so w'' lies in [-6 sigma^2, 6 sigma (5 v - 1)] / R^2: the
// first magnitude falls with v, the second peaks at v = 0.6 (4.8 / R^2).
// Summing the two terms' largest magnitudes instead would give 30 / R^2.
double weightCurvatureBound(const Interval& distance, double R) {
    const double R2 = R * R;
    const double lo = std::min(distance.lo * distance.lo / R2, 1.0), hi = std::min(distance.hi * distance.hi / R2, 1.0);
    auto rising = [](double v) { return 6.0 * (1.0 - v) * (5.0 * v - 1.0); };
    const double peak = hi <= 0.6 ? rising(hi) : lo >= 0.6 ? rising(lo) : 4.8;
    return std::max(6.0 * (1.0 - lo) * (1.0 - lo), peak) / R2 * (1 + 1e-12);
}

// The same for |w'''|: w''' = s' (36 sigma / R^2 - 6 s'^2) with
// 0 <= |s'| <= P = 2 x / R, x = r / R. Over s' in [0, P] its magnitude is
// largest at s' = sqrt(2 sigma) / R (24 sqrt 2 sigma^1.5 / R^3, falling with
// x) or at s' = P (|72 x - 120 x^3| / R^3, extreme at x^2 = 0.2 and at the
// interval's ends).
double weightThirdBound(const Interval& distance, double R) {
    const double lo = std::min(distance.lo / R, 1.0), hi = std::min(distance.hi / R, 1.0);
    const double sigma = 1.0 - lo * lo;
    auto atEnd = [](double x) { return std::abs(72.0 * x - 120.0 * x * x * x); };
    double bound = std::max({24.0 * std::sqrt(2.0) * sigma * std::sqrt(sigma), atEnd(lo), atEnd(hi)});
    const double critical = std::sqrt(0.2);
    if (lo < critical && critical < hi) bound = std::max(bound, atEnd(critical));
    return bound / (R * R * R) * (1 + 1e-12);
}

// The Taylor terms of N at a model's centre, summed in locals (in
// registers, not through the model's memory: a fit adds dozens).
struct TaylorSums {
    double value = 0.0;
    double gradient[3] = {0.0, 0.0, 0.0};
    double hessian[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};  ///< xx xy xz yy yz zz

    // Adds w Q's value, gradient and Hessian at the centre, r from the
    // ball's centre (inside it): the Hessian is
    // Q Hw + dw gq^T + gq dw^T + w Hq, with Hw = 6 sigma ds ds^T - 6 sigma^2 / R^2 I
    // and Hq = 2 A (A symmetric).
    void add(const MpuQuadric& q, double qc, const Vec3& gq, const Vec3& r, double R2) {
        const double sigma = 1.0 - r.squaredNorm() / R2, w = sigma * sigma * sigma;
        const double ds[3] = {2.0 / R2 * r.x(), 2.0 / R2 * r.y(), 2.0 / R2 * r.z()};
        const double dwScale = -3.0 * sigma * sigma;
        const double dw[3] = {dwScale * ds[0], dwScale * ds[1], dwScale * ds[2]};
        const double g[3] = {gq.x(), gq.y(), gq.z()};
        const double outer = 6.0 * sigma * qc, diagonal = 6.0 * sigma * sigma * qc / R2;
        value += w * qc;
        for (int i = 0; i < 3; ++i) gradient[i] += qc * dw[i] + w * g[i];
        int k = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = i; j < 3; ++j, ++k)
                hessian[k] += outer * ds[i] * ds[j] + dw[i] * g[j] + g[i] * dw[j] + 2.0 * w * q.A(i, j) -
                              (i == j ? diagonal : 0.0);
    }

    void store(MpuNumeratorModel& m) const {
        m.value += value;
        m.gradient += Vec3(gradient[0], gradient[1], gradient[2]);
        int k = 0;
        for (int i = 0; i < 3; ++i)
            for (int j = i; j < 3; ++j, ++k) m.hessian(i, j) = m.hessian(j, i) = hessian[k];
    }
};

}  // namespace

Interval quadraticRange(double value, const Vec3& gradient, const Mat3& A, const Vec3& half) {
    const double linear = gradient.cwiseAbs().dot(half);
    double lo = value - linear, hi = value + linear;
    for (int a = 0; a < 3; ++a) {
        const double diagonal = A(a, a) * half[a] * half[a];
        (diagonal < 0 ? lo : hi) += diagonal;
        for (int b = a + 1; b < 3; ++b) {
            const double cross = 2.0 * std::abs(A(a, b)) * half[a] * half[b];
            lo -= cross;
            hi += cross;
        }
    }
    return {lo, hi};
}

namespace {

// The error sums of a model: M3 (the bound on N's third directional
// derivatives over the box), split into the shares that hold in any box
// inside (see mpuNumeratorModelWithin): single-piece locals', and sharp ones'
// whose crease does not cross the box; the shares of the sharp locals whose
// crease does, and the creases' own errors; and the size of the sums, for
// rounding.
struct ErrorSums {
    double singleThird = 0.0, throughoutSharpThird = 0.0, creasedThird = 0.0;
    double scale = 0.0, creaseValue = 0.0, creaseSlope = 0.0;
};

// Where a crease crosses the box: the local is remembered (for models of
// boxes inside), or all sharp locals are, past kMaxCreased.
void noteCreased(MpuNumeratorModel& m, uint32_t local) {
    if (m.creasedCount < 0) return;
    if (m.creasedCount == MpuNumeratorModel::kMaxCreased) m.creasedCount = -1;
    else m.creased[m.creasedCount++] = local;
}

// One local's share of the model of N over the box c +- half: its Taylor
// terms at c and its bounds over the box.
void addLocal(const MpuField& field, uint32_t index, const Interval& distance, const Vec3& c, const Vec3& half,
              double rho, TaylorSums& taylor, ErrorSums& sums, MpuNumeratorModel& m) {
    const MpuLocal& l = field.locals()[index];
    const double R = l.radius, R2 = R * R;
    const PieceInEffect piece = pieceInEffect(field, l, c, half);
    const MpuQuadric& q = field.pieces()[l.first + piece.index];
    Vec3 gq;
    const double qc = q.evaluate(c, &gq);
    const Vec3 r = c - l.center;
    if (r.squaredNorm() < R2) taylor.add(q, qc, gq, r, R2);
    // Bounds of w's first three directional derivatives over the box.
    const double sigmaMax = 1.0 - distance.lo * distance.lo / R2;
    const double w1 = mpuWeightSlope(distance, R), w2 = weightCurvatureBound(distance, R),
                 w3 = weightThirdBound(distance, R);
    const double hqNorm = 2.0 * field.pieceCurvature(l.first + piece.index);  // at least |u^T Hq u|
    const double q0 = quadraticRange(qc, gq, q.A, half).magnitude(), q1 = gq.norm() + hqNorm * rho;
    const double third = w3 * q0 + 3.0 * w2 * q1 + 3.0 * w1 * hqNorm;
    (l.count == 1 ? sums.singleThird : piece.throughout ? sums.throughoutSharpThird : sums.creasedThird) += third;
    const double w0 = sigmaMax * sigmaMax * sigmaMax;
    sums.scale += w0 * q0;
    if (!piece.throughout) {
        // Where the crease crosses the box the local is any of its
        // pieces: w (S - Q_p) is an error of its own, bounded by the
        // pieces' largest difference from Q_p and their gradients'.
        double difference = 0.0, slopeDifference = 0.0;
        for (int k = 0; k < l.count; ++k) {
            const MpuQuadric& other = field.pieces()[l.first + k];
            Vec3 gk;
            const double vk = other.evaluate(c, &gk);
            difference = std::max(difference, quadraticRange(vk - qc, gk - gq, other.A - q.A, half).magnitude());
            slopeDifference = std::max(slopeDifference, (gk - gq).norm() + 2.0 * (other.A - q.A).norm() * rho);
        }
        sums.creaseValue += w0 * difference;
        sums.creaseSlope += w1 * difference + w0 * slopeDifference;
        noteCreased(m, index);
    }
}

// The errors from the sums, over a box of half diagonal rho.
void setErrors(MpuNumeratorModel& m, const ErrorSums& sums, double rho) {
    const double third = sums.singleThird + sums.throughoutSharpThird + sums.creasedThird;
    // Rounding: exact sums are evaluated to about 1e-16 of their terms.
    const double rounding = 1e-12 * sums.scale;
    const MpuTaylorRemainder remainder = mpuTaylorRemainder(third, rounding, rho, rho);
    m.valueError = remainder.value + sums.creaseValue * (1 + 1e-9);
    m.slopeError = remainder.slope + sums.creaseSlope * (1 + 1e-9);
    m.hessianError = sums.creaseValue > 0.0 || sums.creaseSlope > 0.0
                         ? std::numeric_limits<double>::infinity()
                         : third * rho * (1 + 1e-9) + rounding / std::max(rho * rho, 1e-300);
    m.third = third;
    m.halfDiagonal = rho;
    m.rounding = rounding;
    m.singleThird = sums.singleThird;
    m.throughoutSharpThird = sums.throughoutSharpThird;
    m.scale = sums.scale;
}

}  // namespace

MpuNumeratorModel fitMpuNumeratorModel(const MpuField& field, const Box3& box, std::span<const uint32_t> locals) {
    const Vec3 c = box.center(), half = 0.5 * box.extent();
    const double rho = half.norm();
    MpuNumeratorModel m;
    m.center = c;
    m.value = MpuField::kBackgroundWeight * field.backgroundMargin();  // the background inside the domain
    ErrorSums sums;
    sums.scale = std::abs(m.value);
    TaylorSums taylor;
    for (const uint32_t i : locals) {
        const MpuLocal& l = field.locals()[i];
        const Interval distance = box.distanceRange(l.center);
        if (distance.lo < l.radius) addLocal(field, i, distance, c, half, rho, taylor, sums, m);
    }
    taylor.store(m);
    setErrors(m, sums, rho);
    return m;
}

MpuNumeratorModel mpuNumeratorModelWithin(const MpuField& field, const Box3& box, std::span<const uint32_t> locals,
                                          const MpuNumeratorModel& outer) {
    const Vec3 c = box.center(), half = 0.5 * box.extent();
    const double rho = half.norm();
    MpuNumeratorModel m;
    m.center = c;
    m.value = MpuField::kBackgroundWeight * field.backgroundMargin();
    // Which sharp locals are bounded anew: those whose crease crosses the
    // outer box (their piece in effect differs from box to box), or all of
    // them when outer lost count.
    const bool allSharpAnew = outer.creasedCount < 0;
    auto anew = [&](uint32_t i) {
        return allSharpAnew || std::find(outer.creased, outer.creased + outer.creasedCount, i) !=
                                   outer.creased + outer.creasedCount;
    };
    TaylorSums taylor;
    ErrorSums sums;
    sums.singleThird = outer.singleThird;
    sums.throughoutSharpThird = allSharpAnew ? 0.0 : outer.throughoutSharpThird;
    sums.scale = outer.scale;
    for (const uint32_t i : locals) {
        const MpuLocal& l = field.locals()[i];
        if (l.count > 1 && anew(i)) {
            const Interval distance = box.distanceRange(l.center);
            if (distance.lo < l.radius) addLocal(field, i, distance, c, half, rho, taylor, sums, m);
            continue;
        }
        const Vec3 r = c - l.center;
        const double R2 = l.radius * l.radius;
        if (r.squaredNorm() >= R2) continue;
        // One piece all over the outer box: the one in effect at c.
        const MpuQuadric* q = &field.pieces()[l.first];
        int piece = 0;
        if (l.count > 1) {
            double v[3];
            for (int k = 0; k < l.count; ++k) v[k] = q[k].evaluate(c, nullptr);
            piece = pieceTaken(l, v);
        }
        Vec3 gq;
        const double qc = q[piece].evaluate(c, &gq);
        taylor.add(q[piece], qc, gq, r, R2);
    }
    taylor.store(m);
    setErrors(m, sums, rho);
    return m;
}

}  // namespace isotrace::geometry
