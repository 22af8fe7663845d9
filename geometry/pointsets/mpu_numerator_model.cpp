#include "geometry/pointsets/mpu_numerator_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {

// The upper triangle of a symmetric matrix.
template <class T>
struct Symmetric3 {
    T xx, xy, xz, yy, yz, zz;
};

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

// The piece a local takes at point x.
int pieceAt(const MpuField& field, const MpuLocal& l, const Vec3& x) {
    double v[3];
    for (int k = 0; k < l.count; ++k) v[k] = field.pieces()[l.first + k].evaluate(x, nullptr);
    return pieceTaken(l, v);
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
template <class T>
T weightCurvatureBound(const T& distanceLo, const T& distanceHi, const T& R) {
    const T R2 = R * R;
    const T lo = lesser(T(distanceLo * distanceLo / R2), T(1.0)), hi = lesser(T(distanceHi * distanceHi / R2), T(1.0));
    auto rising = [](const T& v) { return T(6.0 * (1.0 - v) * (5.0 * v - 1.0)); };
    const T peak = select(hi <= 0.6, rising(hi), select(lo >= 0.6, rising(lo), T(4.8)));
    return greater(T(6.0 * (1.0 - lo) * (1.0 - lo)), peak) / R2 * (1 + 1e-12);
}

// The same for |w'''|: w''' = s' (36 sigma / R^2 - 6 s'^2) with
// 0 <= |s'| <= P = 2 x / R, x = r / R. Over s' in [0, P] its magnitude is
// largest at s' = sqrt(2 sigma) / R (24 sqrt 2 sigma^1.5 / R^3, falling with
// x) or at s' = P (|72 x - 120 x^3| / R^3, extreme at x^2 = 0.2 and at the
// interval's ends).
template <class T>
T weightThirdBound(const T& distanceLo, const T& distanceHi, const T& R) {
    using std::abs, std::sqrt;
    const T lo = lesser(T(distanceLo / R), T(1.0)), hi = lesser(T(distanceHi / R), T(1.0));
    const T sigma = 1.0 - lo * lo;
    auto atEnd = [](const T& x) { return T(abs(T(72.0 * x - 120.0 * x * x * x))); };
    const double critical = std::sqrt(0.2);
    const T ends = greater(greater(T(24.0 * std::sqrt(2.0) * sigma * sqrt(sigma)), atEnd(lo)), atEnd(hi));
    const T bound = select(lo < critical, select(critical < hi, greater(ends, atEnd(T(critical))), ends), ends);
    return bound / (R * R * R) * (1 + 1e-12);
}

// The same for |w''''|, where the ball holds the whole box (w is smooth
// there): w'''' = -36 s'^2 s'' + 18 sigma s''^2, two terms of opposite
// signs, the first at most 288 x^2 / R^4, the second 72 sigma / R^4.
template <class T>
T weightFourthBound(const T& distanceLo, const T& distanceHi, const T& R) {
    const T lo = lesser(T(distanceLo / R), T(1.0)), hi = lesser(T(distanceHi / R), T(1.0));
    const T R2 = R * R;
    return greater(T(288.0 * hi * hi), T(72.0 * (1.0 - lo * lo))) / (R2 * R2) * (1 + 1e-12);
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

namespace {

// quadraticRange for doubles and lanes alike.
template <class T>
struct RangeOf {
    T lo, hi;
    T magnitude() const {
        using std::abs;
        return greater(T(abs(lo)), T(abs(hi)));
    }
};
template <class T>
RangeOf<T> quadraticRangeOf(const T& value, const T& gx, const T& gy, const T& gz, const Symmetric3<T>& a,
                            const T& hx, const T& hy, const T& hz) {
    using std::abs;
    const T linear = abs(gx) * hx + abs(gy) * hy + abs(gz) * hz;
    const T dx = a.xx * hx * hx, dy = a.yy * hy * hy, dz = a.zz * hz * hz;
    const T cross = 2.0 * (abs(a.xy) * hx * hy + abs(a.xz) * hx * hz + abs(a.yz) * hy * hz);
    const T zero(0.0);
    const T lo = value - linear + (lesser(dx, zero) + lesser(dy, zero) + lesser(dz, zero)) - cross;
    const T hi = value + linear + (greater(dx, zero) + greater(dy, zero) + greater(dz, zero)) + cross;
    return {lo, hi};
}

}  // namespace

Interval quadraticRange(double value, const Vec3& gradient, const Mat3& A, const Vec3& half) {
    const RangeOf<double> r = quadraticRangeOf<double>(value, gradient.x(), gradient.y(), gradient.z(),
                                                       {A(0, 0), A(0, 1), A(0, 2), A(1, 1), A(1, 2), A(2, 2)},
                                                       half.x(), half.y(), half.z());
    return {r.lo, r.hi};
}

namespace {

// The error sums of a model: M3 (the bound on N's third directional
// derivatives over the box), the creases' own errors, and the size of the
// sums, for rounding.
struct ErrorSums {
    /// M3 over the box, and what stands for it in the remainders of value,
    /// slope and Hessian (see thirdFromCentre).
    double third = 0.0, valueThird = 0.0, slopeThird = 0.0, hessianThird = 0.0;
    /// Errors of balls bounded directly, the same at any distance.
    double directValue = 0.0, directSlope = 0.0, directHessian = 0.0;
    /// What the value error over the whole box sheds where the third
    /// derivatives at the centre are bounded over the box itself
    /// (SingleSums::cubicOverBox) rather than over the ball of its half
    /// diagonal.
    double cubicSaving = 0.0;
    double scale = 0.0, creaseValue = 0.0, creaseSlope = 0.0;

    void addThird(double bound) {
        third += bound;
        valueThird += bound;
        slopeThird += bound;
        hessianThird += bound;
    }
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
    const double w1 = mpuWeightSlope(distance, R), w2 = weightCurvatureBound(distance.lo, distance.hi, R),
                 w3 = weightThirdBound(distance.lo, distance.hi, R);
    const double hqNorm = 2.0 * field.pieceCurvature(l.first + piece.index);  // at least |u^T Hq u|
    const double q0 = quadraticRange(qc, gq, q.A, half).magnitude(), q1 = gq.norm() + hqNorm * rho;
    sums.addThird(w3 * q0 + 3.0 * w2 * q1 + 3.0 * w1 * hqNorm);
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
    // Rounding: exact sums are evaluated to about 1e-16 of their terms.
    const double rounding = 1e-12 * sums.scale;
    m.valueFloor = rounding + sums.directValue;
    m.slopeFloor = rounding / std::max(rho, 1e-300) + sums.directSlope;
    m.valueError = mpuTaylorRemainder(sums.valueThird, rho, m.valueFloor, m.slopeFloor).value -
                   sums.cubicSaving * (1 - 1e-9) + sums.creaseValue * (1 + 1e-9);
    m.slopeError =
        mpuTaylorRemainder(sums.slopeThird, rho, m.valueFloor, m.slopeFloor).slope + sums.creaseSlope * (1 + 1e-9);
    m.hessianError = sums.creaseValue > 0.0 || sums.creaseSlope > 0.0
                         ? std::numeric_limits<double>::infinity()
                         : sums.hessianThird * rho * (1 + 1e-9) + rounding / std::max(rho * rho, 1e-300) +
                               sums.directHessian;
    m.third = sums.third;
    m.remainderThird = sums.slopeThird;  // the larger of value's and slope's
}

}  // namespace

void MpuLocalColumns::fill(const MpuField& field, std::span<const uint32_t> locals, std::span<const uint8_t> pieces) {
    singleCount_ = locals.size();
    // Columns padded with zeros to whole vectors (the sums mask the padding).
    stride_ = (singleCount_ + Lanes::size() - 1) / Lanes::size() * Lanes::size();
    data_.assign(stride_ * kColumns, 0.0);
    for (size_t k = 0; k < locals.size(); ++k) {
        const MpuLocal& l = field.locals()[locals[k]];
        const uint32_t piece = l.first + pieces[k];
        const MpuQuadric& q = field.pieces()[piece];
        const double values[kColumns] = {l.center.x(), l.center.y(), l.center.z(), l.radius, 1.0 / (l.radius * l.radius),
                                         q.origin.x(), q.origin.y(), q.origin.z(), q.A(0, 0), q.A(0, 1), q.A(0, 2),
                                         q.A(1, 1), q.A(1, 2), q.A(2, 2), q.g.x(), q.g.y(), q.g.z(), q.c0,
                                         field.pieceCurvature(piece)};
        for (int c = 0; c < kColumns; ++c) data_[size_t(c) * stride_ + k] = values[c];
    }
}

void MpuLocalColumns::assign(const MpuField& field, std::span<const uint32_t> locals) {
    sharp_.clear();
    indices_.clear();
    for (const uint32_t i : locals)
        (field.locals()[i].combination == MpuCombination::Single ? indices_ : sharp_).push_back(i);
    pieces_.assign(indices_.size(), 0);
    fill(field, indices_, pieces_);
}

uint32_t mpuResolvedSharpPieces(const MpuField& field, const MpuNumeratorModel& m, const MpuLocalList& list) {
    uint32_t codes = 0;
    const std::span<const uint32_t> others = list.otherLocals();
    for (size_t k = 0; k < std::min(others.size(), MpuLocalList::kResolvedSharp); ++k) {
        const MpuLocal& l = field.locals()[others[k]];
        if (l.combination == MpuCombination::Interpolant || m.mayCrease(others[k])) continue;
        codes |= MpuLocalList::pieceCode(k, pieceAt(field, l, m.center));
    }
    return codes;
}

void MpuLocalColumns::assignResolved(const MpuField& field, const MpuLocalColumns* ancestor,
                                     std::span<const uint32_t> sharp, const MpuNumeratorModel& outer) {
    sharp_.clear();
    indices_.clear();
    pieces_.clear();
    if (ancestor) {
        indices_.assign(ancestor->indices_.begin(), ancestor->indices_.end());
        pieces_.assign(ancestor->pieces_.begin(), ancestor->pieces_.end());
    }
    for (const uint32_t i : sharp) {
        if (outer.mayCrease(i)) {
            sharp_.push_back(i);
            continue;
        }
        // One piece all over the outer box: the one in effect at its centre
        // (any piece, for a ball that misses the box: it adds nothing).
        indices_.push_back(i);
        pieces_.push_back(uint8_t(pieceAt(field, field.locals()[i], outer.center)));
    }
    fill(field, indices_, pieces_);
}

namespace {

// Single-piece locals from the columns, Lanes::size() at a time; the
// columns are padded to whole vectors, and the padding's lanes are masked.
struct LaneLoader {
    const MpuLocalColumns& columns;
    size_t first;  ///< the first local of the lanes
    Lanes operator()(MpuLocalColumns::Column c) const {
        return Lanes(columns.column(c) + first, std::experimental::element_aligned);
    }
};

// The lanes' quadrics at p (value and gradient), and what each adds to N's
// Taylor terms there: TaylorSums::add, lane by lane. Every term carries
// sigma, so a lane whose ball misses p (or a padding lane) adds nothing.
struct LaneTerms {
    Lanes q, gqx, gqy, gqz;
    Lanes value, gx, gy, gz, hxx, hxy, hxz, hyy, hyz, hzz;
};

LaneTerms laneTerms(const LaneLoader& load, const Vec3& p, const Lanes::mask_type& valid) {
    using C = MpuLocalColumns;
    LaneTerms t;
    const Lanes yx = p.x() - load(C::OriginX), yy = p.y() - load(C::OriginY), yz = p.z() - load(C::OriginZ);
    const Lanes axx = load(C::Axx), axy = load(C::Axy), axz = load(C::Axz), ayy = load(C::Ayy), ayz = load(C::Ayz),
                azz = load(C::Azz);
    const Lanes ayX = axx * yx + axy * yy + axz * yz, ayY = axy * yx + ayy * yy + ayz * yz,
                ayZ = axz * yx + ayz * yy + azz * yz;
    const Lanes gx = load(C::Gx), gy = load(C::Gy), gz = load(C::Gz);
    t.q = load(C::C0) + (gx * yx + gy * yy + gz * yz) + (yx * ayX + yy * ayY + yz * ayZ);
    t.gqx = gx + 2.0 * ayX;
    t.gqy = gy + 2.0 * ayY;
    t.gqz = gz + 2.0 * ayZ;
    const Lanes rx = p.x() - load(C::CenterX), ry = p.y() - load(C::CenterY), rz = p.z() - load(C::CenterZ);
    const Lanes inverseR2 = load(C::InverseRadius2);
    const Lanes s = 1.0 - (rx * rx + ry * ry + rz * rz) * inverseR2;
    const Lanes sigma = select(valid && s > 0.0, s, Lanes(0.0)), w = sigma * sigma * sigma;
    const Lanes dsx = 2.0 * inverseR2 * rx, dsy = 2.0 * inverseR2 * ry, dsz = 2.0 * inverseR2 * rz;
    const Lanes dwScale = -3.0 * sigma * sigma;
    const Lanes dwx = dwScale * dsx, dwy = dwScale * dsy, dwz = dwScale * dsz;
    const Lanes outer = 6.0 * sigma * t.q, diagonal = 6.0 * sigma * sigma * t.q * inverseR2;
    t.value = w * t.q;
    t.gx = t.q * dwx + w * t.gqx;
    t.gy = t.q * dwy + w * t.gqy;
    t.gz = t.q * dwz + w * t.gqz;
    t.hxx = outer * dsx * dsx + dwx * t.gqx + t.gqx * dwx + 2.0 * w * axx - diagonal;
    t.hxy = outer * dsx * dsy + dwx * t.gqy + t.gqx * dwy + 2.0 * w * axy;
    t.hxz = outer * dsx * dsz + dwx * t.gqz + t.gqx * dwz + 2.0 * w * axz;
    t.hyy = outer * dsy * dsy + dwy * t.gqy + t.gqy * dwy + 2.0 * w * ayy - diagonal;
    t.hyz = outer * dsy * dsz + dwy * t.gqz + t.gqy * dwz + 2.0 * w * ayz;
    t.hzz = outer * dsz * dsz + dwz * t.gqz + t.gqz * dwz + 2.0 * w * azz - diagonal;
    return t;
}

// Adds each `holds` lane's third derivatives of w Q at p to tensor
// (xxx xxy xxz xyy xyz xzz yyy yyz yzz zzz): with a = grad sigma =
// -2 r / R^2, grad w = 3 sigma^2 a, Hw = 6 sigma a a^T - 6 sigma^2 / R^2 I and
//   D3w_ijk = 6 a_i a_j a_k - 12 sigma / R^2 (d_ik a_j + d_jk a_i + d_ij a_k),
//   D3(w Q)_ijk = D3w_ijk Q + Hw_ij gQ_k + Hw_ik gQ_j + Hw_jk gQ_i
//                 + dw_i HQ_jk + dw_j HQ_ik + dw_k HQ_ij,  HQ = 2 A.
void addThirdDerivatives(const LaneLoader& load, const Vec3& p, const LaneTerms& t, const Lanes::mask_type& holds,
                         Lanes* tensor) {
    using C = MpuLocalColumns;
    const Lanes inverseR2 = load(C::InverseRadius2);
    const Lanes r[3] = {p.x() - load(C::CenterX), p.y() - load(C::CenterY), p.z() - load(C::CenterZ)};
    const Lanes sigma = select(holds, Lanes(1.0 - (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) * inverseR2), Lanes(0.0));
    const Lanes a[3] = {-2.0 * inverseR2 * r[0], -2.0 * inverseR2 * r[1], -2.0 * inverseR2 * r[2]};
    const Lanes g[3] = {t.gqx, t.gqy, t.gqz};
    const Lanes dw[3] = {3.0 * sigma * sigma * a[0], 3.0 * sigma * sigma * a[1], 3.0 * sigma * sigma * a[2]};
    const Lanes twoA[6] = {2.0 * load(C::Axx), 2.0 * load(C::Axy), 2.0 * load(C::Axz),
                           2.0 * load(C::Ayy), 2.0 * load(C::Ayz), 2.0 * load(C::Azz)};
    auto hq = [&](int i, int j) {
        static constexpr int kIndex[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
        return twoA[kIndex[i][j]];
    };
    const Lanes sixSigma = 6.0 * sigma, diagonal = 6.0 * sigma * sigma * inverseR2, twelve = 12.0 * sigma * inverseR2;
    auto hw = [&](int i, int j) { return Lanes(sixSigma * a[i] * a[j] - (i == j ? diagonal : Lanes(0.0))); };
    int slot = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            for (int k = j; k < 3; ++k, ++slot) {
                Lanes w3 = 6.0 * a[i] * a[j] * a[k];
                if (i == k) w3 -= twelve * a[j];
                if (j == k) w3 -= twelve * a[i];
                if (i == j) w3 -= twelve * a[k];
                const Lanes term = w3 * t.q + hw(i, j) * g[k] + hw(i, k) * g[j] + hw(j, k) * g[i] + dw[i] * hq(j, k) +
                                   dw[j] * hq(i, k) + dw[k] * hq(i, j);
                tensor[slot] += select(holds, term, Lanes(0.0));
            }
}

// Sums of the single-piece locals' terms (the order of the sums changes
// with the lane count, within their rounding allowance).
struct SingleSums {
    double value = 0.0, gradient[3] = {}, hessian[6] = {};
    double scale = 0.0;
    /// M3's shares: the sum of the locals' own bounds; N's third derivatives
    /// at the centre (xxx xxy xxz xyy xyz xzz yyy yyz yzz zzz) and the bound
    /// on the fourth over the box of the locals taken from the centre; the
    /// own bounds of the others.
    double ownThird = 0.0, tensor[10] = {}, fourth = 0.0, apart = 0.0;
    /// Of the others, those whose rim crosses the box and whose weight
    /// stays small over it: their own bounds (part of `apart`), and their
    /// errors bounded directly.
    double directOwn = 0.0, directValue = 0.0, directSlope = 0.0, directHessian = 0.0;

    void addShares(const SingleSums& o) {
        ownThird += o.ownThird;
        scale += o.scale;
        for (int j = 0; j < 10; ++j) tensor[j] += o.tensor[j];
        fourth += o.fourth;
        apart += o.apart;
        directOwn += o.directOwn;
        directValue += o.directValue;
        directSlope += o.directSlope;
        directHessian += o.directHessian;
    }
    /// The largest |T[y, y, y]| over |y_k| <= half_k: at most the terms'
    /// magnitudes summed, which for a tensor that is not spread evenly over
    /// the axes is well below tensorNorm() |half|^3.
    double cubicOverBox(const Vec3& half) const {
        static constexpr int kAxes[10][3] = {{0, 0, 0}, {0, 0, 1}, {0, 0, 2}, {0, 1, 1}, {0, 1, 2},
                                             {0, 2, 2}, {1, 1, 1}, {1, 1, 2}, {1, 2, 2}, {2, 2, 2}};
        static constexpr double kMultiplicity[10] = {1, 3, 3, 3, 6, 3, 1, 3, 3, 1};
        double sum = 0.0;
        for (int j = 0; j < 10; ++j)
            sum += kMultiplicity[j] * std::abs(tensor[j]) * half[kAxes[j][0]] * half[kAxes[j][1]] * half[kAxes[j][2]];
        return sum;
    }
    /// max |T[u, u, u]| over unit u is at most T's Frobenius norm.
    double tensorNorm() const {
        static constexpr double kMultiplicity[10] = {1, 3, 3, 3, 6, 3, 1, 3, 3, 1};
        double sum = 0.0;
        for (int j = 0; j < 10; ++j) sum += kMultiplicity[j] * tensor[j] * tensor[j];
        return std::sqrt(sum);
    }

    void addTo(TaylorSums& taylor) const {
        taylor.value += value;
        for (int j = 0; j < 3; ++j) taylor.gradient[j] += gradient[j];
        for (int j = 0; j < 6; ++j) taylor.hessian[j] += hessian[j];
    }
};

// The single-piece locals' Taylor terms at c; with a box (centre c, half
// diagonal rho), also their share of M3 and of the sums' size over it.
// Each local's share of M3 is either its own bound (what addLocal gives it)
// or, where its ball holds the whole box (w is smooth over it) and this is
// smaller, its fourth-derivative bound times rho, its third derivatives at
// c going to SingleSums::tensor (see thirdFromCentre).
SingleSums sumSingles(const MpuLocalColumns& columns, const Vec3& c, const Box3* box = nullptr, double rho = 0.0) {
    using C = MpuLocalColumns;
    using std::experimental::reduce;
    const Vec3 half = box ? Vec3(0.5 * box->extent()) : Vec3::Zero();
    Lanes value = 0.0, gx = 0.0, gy = 0.0, gz = 0.0, hxx = 0.0, hxy = 0.0, hxz = 0.0, hyy = 0.0, hyz = 0.0, hzz = 0.0;
    Lanes ownThird = 0.0, scale = 0.0, fourth = 0.0, apart = 0.0;
    Lanes directOwn = 0.0, directValue = 0.0, directSlope = 0.0, directHessian = 0.0;
    Lanes tensor[10];
    for (Lanes& t : tensor) t = 0.0;
    const size_t n = columns.singleCount();
    for (size_t first = 0; first < n; first += Lanes::size()) {
        const LaneLoader load{columns, first};
        const Lanes::mask_type valid = firstLanes(n - first);
        const LaneTerms t = laneTerms(load, c, valid);
        value += t.value;
        gx += t.gx;
        gy += t.gy;
        gz += t.gz;
        hxx += t.hxx;
        hxy += t.hxy;
        hxz += t.hxz;
        hyy += t.hyy;
        hyz += t.hyz;
        hzz += t.hzz;
        if (!box) continue;
        // The distances from the ball's centre to the box.
        using std::experimental::abs, std::experimental::sqrt;
        auto gap = [&](C::Column centre, int axis) {
            const Lanes x = load(centre);
            return greater(greater(Lanes(box->lower[axis] - x), Lanes(0.0)), Lanes(x - box->upper[axis]));
        };
        auto far = [&](C::Column centre, int axis) {
            const Lanes x = load(centre);
            return greater(Lanes(abs(x - box->lower[axis])), Lanes(abs(x - box->upper[axis])));
        };
        const Lanes ex = gap(C::CenterX, 0), ey = gap(C::CenterY, 1), ez = gap(C::CenterZ, 2);
        const Lanes fx = far(C::CenterX, 0), fy = far(C::CenterY, 1), fz = far(C::CenterZ, 2);
        const Lanes gap2 = ex * ex + ey * ey + ez * ez;
        const Lanes nearest = sqrt(gap2), farthest = sqrt(fx * fx + fy * fy + fz * fz);
        const Lanes R = load(C::Radius);
        const Lanes sigmaMax = 1.0 - gap2 * load(C::InverseRadius2);
        const Lanes w1 = mpuWeightSlope(nearest, farthest, R), w2 = weightCurvatureBound(nearest, farthest, R),
                    w3 = weightThirdBound(nearest, farthest, R);
        const Lanes hqNorm = 2.0 * load(C::Curvature);  // at least |u^T Hq u|
        const Symmetric3<Lanes> a{load(C::Axx), load(C::Axy), load(C::Axz), load(C::Ayy), load(C::Ayz), load(C::Azz)};
        const Lanes q0 =
            quadraticRangeOf(t.q, t.gqx, t.gqy, t.gqz, a, Lanes(half.x()), Lanes(half.y()), Lanes(half.z())).magnitude();
        const Lanes q1 = sqrt(t.gqx * t.gqx + t.gqy * t.gqy + t.gqz * t.gqz) + hqNorm * rho;
        // Padding lanes have R = 0: no distance is below it.
        const Lanes::mask_type reaches = valid && nearest < R;
        const Lanes own = w3 * q0 + 3.0 * w2 * q1 + 3.0 * w1 * hqNorm;
        ownThird += select(reaches, own, Lanes(0.0));
        scale += select(reaches, Lanes(sigmaMax * sigmaMax * sigmaMax * q0), Lanes(0.0));
        // (w Q)'''' = w'''' Q + 4 w''' Q' + 6 w'' Q'' (Q''' = 0).
        const Lanes own4 = weightFourthBound(nearest, farthest, R) * q0 + 4.0 * w3 * q1 + 6.0 * w2 * hqNorm;
        const Lanes::mask_type fromCentre = reaches && farthest < R && own4 * rho < own;
        fourth += select(fromCentre, own4, Lanes(0.0));
        const Lanes::mask_type others = reaches && !fromCentre;
        apart += select(others, own, Lanes(0.0));
        if (any_of(fromCentre)) addThirdDerivatives(load, c, t, fromCentre, tensor);
        if (none_of(others)) continue;
        // A ball whose rim crosses the box: w Q - T_i (T_i its Taylor terms
        // at c) is at most max w |Q| + max |T_i| over the box, and likewise
        // for slope and curvature. Near the rim w = sigma^3 is small, and
        // this is well below Taylor's remainder of its own bound, which the
        // jump of w's third derivative at the rim makes large (on the
        // 37,934-vertex model those remainders were most of the value
        // errors).
        const Lanes w0 = sigmaMax * sigmaMax * sigmaMax;
        const Lanes hx = half.x(), hy = half.y(), hz = half.z();
        const Lanes taylorRange = abs(t.value) + abs(t.gx) * hx + abs(t.gy) * hy + abs(t.gz) * hz +
                                  0.5 * (abs(t.hxx) * hx * hx + abs(t.hyy) * hy * hy + abs(t.hzz) * hz * hz) +
                                  abs(t.hxy) * hx * hy + abs(t.hxz) * hx * hz + abs(t.hyz) * hy * hz;
        const Lanes taylorSlope = sqrt(t.gx * t.gx + t.gy * t.gy + t.gz * t.gz);
        const Lanes taylorHessian = sqrt(t.hxx * t.hxx + t.hyy * t.hyy + t.hzz * t.hzz +
                                         2.0 * (t.hxy * t.hxy + t.hxz * t.hxz + t.hyz * t.hyz));
        const Lanes value = w0 * q0 + taylorRange;
        const Lanes::mask_type direct = others && value < own * (rho * rho * rho / 6.0);
        directOwn += select(direct, own, Lanes(0.0));
        directValue += select(direct, value, Lanes(0.0));
        directSlope += select(direct, Lanes(w1 * q0 + w0 * q1 + taylorSlope + taylorHessian * rho), Lanes(0.0));
        directHessian += select(direct, Lanes(w2 * q0 + 2.0 * w1 * q1 + w0 * hqNorm + taylorHessian), Lanes(0.0));
    }
    SingleSums sums;
    sums.value = reduce(value);
    sums.gradient[0] = reduce(gx);
    sums.gradient[1] = reduce(gy);
    sums.gradient[2] = reduce(gz);
    const Lanes* hessian[6] = {&hxx, &hxy, &hxz, &hyy, &hyz, &hzz};
    for (int j = 0; j < 6; ++j) sums.hessian[j] = reduce(*hessian[j]);
    sums.ownThird = reduce(ownThird);
    sums.scale = reduce(scale);
    for (int j = 0; j < 10; ++j) sums.tensor[j] = reduce(tensor[j]);
    sums.fourth = reduce(fourth);
    sums.apart = reduce(apart);
    sums.directOwn = reduce(directOwn);
    sums.directValue = reduce(directValue);
    sums.directSlope = reduce(directSlope);
    sums.directHessian = reduce(directHessian);
    return sums;
}

// M3's single-piece share: the third derivatives of the locals taken from
// the centre move at most their M4 times rho from their value there (M4
// bounds pure directional fourth derivatives; for symmetric forms that
// bounds the mixed ones too, Banach 1938), and the others keep their own
// bounds. Where the weights' third derivatives cancel across locals (they
// sum to W's, which varies slowly), this is well below the sum of the
// locals' own bounds (on the smooth fit of mpu_numerator_model_test the
// model errors reached 0.31 of their bound, against 0.12 with the own
// bounds alone, the same boxes and points); never above it. The tensor's
// rounding is far below 1e-9 of the bounds it is summed from.
//
// `reach` is the share of rho the fourth derivatives' bound is taken over:
// 1 for M3 itself. Taylor's remainders integrate the third derivatives
// along the way out from the centre, where at distance s they are within
// M4 s of their value there: the value's remainder is at most
// |T3| r^3 / 6 + M4 r^4 / 24, the slope's |T3| r^2 / 2 + M4 r^3 / 6 and the
// Hessian's |T3| r + M4 r^2 / 2, those of M3 = |T3| + M4 rho times 1/4, 1/3
// and 1/2 (r <= rho). On the 37,934-vertex model the fourth derivatives'
// share was 46% of M3.
//
// With `direct`, the balls bounded directly are left out (their bounds go
// to the errors apart), and the locals' own bounds are not the fallback.
double thirdFromCentre(const SingleSums& sums, double rho, double reach = 1.0, bool direct = false) {
    const double apart = direct ? std::max(sums.apart - sums.directOwn, 0.0) + 1e-9 * sums.apart : sums.apart;
    const double fromCentre =
        sums.tensorNorm() + sums.fourth * rho * reach * (1 + 1e-12) + apart + 1e-9 * sums.ownThird;
    return direct ? fromCentre : std::min(sums.ownThird, fromCentre);
}

}  // namespace

MpuNumeratorModel fitMpuNumeratorModel(const MpuField& field, const Box3& box, const MpuLocalColumns& locals,
                                       const MpuLocalColumns* resolved) {
    const Vec3 c = box.center(), half = 0.5 * box.extent();
    const double rho = half.norm();
    MpuNumeratorModel m;
    m.center = c;
    m.value = MpuField::kBackgroundWeight * field.backgroundMargin();  // the background inside the domain
    ErrorSums sums;
    sums.scale = std::abs(m.value);
    TaylorSums taylor;
    // Locals of one piece all over the box, the resolved sharp ones too:
    // their bounds are single pieces'.
    SingleSums singles;
    for (const MpuLocalColumns* columns : {&locals, resolved}) {
        if (!columns) continue;
        const SingleSums some = sumSingles(*columns, c, &box, rho);
        some.addTo(taylor);
        singles.addShares(some);
    }
    sums.third = thirdFromCentre(singles, rho);
    // The remainders of the third derivatives from the centre with the
    // balls bounded directly apart, where that is smaller over the box:
    // one choice for value, slope and curvature, as tracers narrow the
    // remainders nearer the centre over the same floors.
    const double cube = rho * rho * rho / 6.0;
    const double valueApart = thirdFromCentre(singles, rho, 1.0 / 4.0, true);
    const double valueTaylor = thirdFromCentre(singles, rho, 1.0 / 4.0);
    const bool direct = singles.directOwn > 0.0 && valueApart * cube + singles.directValue < valueTaylor * cube;
    sums.valueThird = direct ? valueApart : valueTaylor;
    sums.slopeThird = thirdFromCentre(singles, rho, 1.0 / 3.0, direct);
    sums.hessianThird = thirdFromCentre(singles, rho, 1.0 / 2.0, direct);
    if (direct || sums.valueThird < singles.ownThird)
        sums.cubicSaving = std::max(0.0, singles.tensorNorm() * rho * rho * rho - singles.cubicOverBox(half)) / 6.0;
    if (direct) {
        sums.directValue = singles.directValue * (1 + 1e-9);
        sums.directSlope = singles.directSlope * (1 + 1e-9);
        sums.directHessian = singles.directHessian * (1 + 1e-9);
    }
    sums.scale += singles.scale;
    for (const uint32_t i : (resolved ? resolved : &locals)->sharp()) {
        const MpuLocal& l = field.locals()[i];
        const Interval distance = box.distanceRange(l.center);
        if (distance.lo < l.radius) addLocal(field, i, distance, c, half, rho, taylor, sums, m);
    }
    taylor.store(m);
    setErrors(m, sums, rho);
    return m;
}

}  // namespace isotrace::geometry
