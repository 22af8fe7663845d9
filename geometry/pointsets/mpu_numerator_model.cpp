#include "geometry/pointsets/mpu_numerator_model.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/instruction_set.h"
#include "geometry/pointsets/mpu_model_kernels.h"
#include "geometry/pointsets/mpu_weight_bounds.h"

namespace isotrace::geometry {

static_assert(int(MpuLocalColumns::kColumns) == int(MpuModelColumn::kColumns) &&
                  int(MpuLocalColumns::Curvature) == int(MpuModelColumn::Curvature) &&
                  int(MpuLocalColumns::C0) == int(MpuModelColumn::C0) &&
                  int(MpuLocalColumns::OriginX) == int(MpuModelColumn::OriginX),
              "the kernels read the columns in MpuLocalColumns' order");

const MpuModelKernels& mpuModelKernels() {
    static const MpuModelKernels& chosen =
        tableForActiveSet(sse2::kMpuModelKernels, avx2::kMpuModelKernels, avx512::kMpuModelKernels);
    return chosen;
}

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
    // Columns padded with zeros to whole vectors of the widest kernel (the
    // sums mask the padding).
    stride_ = (singleCount_ + kMpuModelColumnPadding - 1) / kMpuModelColumnPadding * kMpuModelColumnPadding;
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

// Sums of the single-piece locals' terms (the order of the sums changes
// with the lane count, within their rounding allowance).
struct SingleSums : MpuColumnSums {
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

// The single-piece locals' sums at c (the kernels of the active instruction
// set, mpu_model_kernels.h); with a box (centre c, half diagonal rho), also
// their share of M3 and of the sums' size over it.
SingleSums sumSingles(const MpuLocalColumns& columns, const Vec3& c, const Box3& box, double rho) {
    SingleSums sums;
    mpuModelKernels().sumColumns(columns.column(MpuLocalColumns::CenterX), columns.stride(), columns.singleCount(),
                                 c.data(), box.lower.data(), box.upper.data(), rho, sums);
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
        const SingleSums some = sumSingles(*columns, c, box, rho);
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
