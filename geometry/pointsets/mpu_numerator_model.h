// A second-order Taylor model of an MPU field's numerator over a box, with
// proven errors. f = N / W with W > 0, so f and N = sum_i w_i Q_i (plus the
// background's constant term inside the domain) share their zeros; about
// the box's centre c,
//   T(x) = N(c) + g . y + y^T H y / 2,  y = x - c,
// and over the box |N - T| <= valueError, |d/du (N - T)| <= slopeError for
// every unit u. Where |T| exceeds valueError, N has T's sign; where T's
// slope along a ray beats slopeError, N is monotone along it. Tracers use
// it to prove most of a ray's signs without a single local function.
//
// The errors: N's second derivatives are Lipschitz (each weight is C^2 at
// its ball's rim), so with M3 bounding every third directional derivative
// over the box, Taylor's remainder gives |N - T| <= M3 rho^3 / 6 and
// |d/du (N - T)| <= M3 rho^2 / 2, rho the box's half diagonal. Per local
// along a unit direction, with s = |x - c_i|^2 / R^2 and sigma = 1 - s in
// [0, 1] inside the ball, |s'| <= 2 r / R^2, s'' = 2 / R^2:
//   w' = -3 sigma^2 s',  w'' = 6 sigma s'^2 - 3 sigma^2 s'',
//   w''' = -6 s'^3 + 18 sigma s' s'',
//   (w Q)''' = w''' Q + 3 w'' Q' + 3 w' Q''  (Q''' = 0).
// A sharp local (a max or min of pieces) is one of its pieces where they do
// not cross. Where its crease crosses the box, T takes the piece in effect
// at the centre, and the others' differences from it (times the weight, and
// their slopes') add to the errors: S - Q_p is always some Q_k - Q_p.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/bounding_box.h"
#include "geometry/interval.h"
#include "geometry/pointsets/mpu_field.h"

namespace isotrace::geometry {

struct MpuNumeratorModel {
    Vec3 center = Vec3::Zero();
    double value = 0.0;
    Vec3 gradient = Vec3::Zero();
    Mat3 hessian = Mat3::Zero();
    double valueError = 0.0, slopeError = 0.0;
    /// |u^T (D^2 N - H) u| over the box for unit u: N's Hessian is
    /// Lipschitz (M3) where no crease crosses the box; infinite where one
    /// does.
    double hessianError = 0.0;
    /// M3, the bound on N's third directional derivatives over the box.
    double third = 0.0;
    /// Value and slope errors that do not shrink nearer the centre: the
    /// sums' rounding, and the balls whose rim crosses the box bounded
    /// directly (their weight is small over it) rather than by Taylor.
    double valueFloor = 0.0, slopeFloor = 0.0;
    /// What stands for M3 in Taylor's remainders of value and slope within
    /// the box (mpuTaylorRemainder; at most `third`): within distance r of
    /// the centre, value and slope errors are mpuTaylorRemainder at r (plus
    /// the creases' share, where valueError and slopeError hold instead).
    /// Where N's third derivatives are taken from their values T3 at the
    /// centre and M4 bounds the fourth, the remainders integrate
    /// |T3| + M4 s at distance s, not the worst |T3| + M4 rho all along:
    /// value |T3| r^3 / 6 + M4 r^4 / 24, slope |T3| r^2 / 2 + M4 r^3 / 6,
    /// within those of |T3| + M4 rho / 3 for r <= rho.
    double remainderThird = 0.0;
    /// The sharp locals whose crease may cross the box (all of them when
    /// creasedCount is -1, past kMaxCreased): boxes inside resolve the
    /// others to one piece (MpuLocalColumns::assignResolved).
    static constexpr int kMaxCreased = 6;
    uint32_t creased[kMaxCreased] = {};
    int creasedCount = 0;

    /// The crease of sharp local `local` may cross the box (it is listed,
    /// or the model lost count).
    bool mayCrease(uint32_t local) const {
        return creasedCount < 0 || std::find(creased, creased + creasedCount, local) != creased + creasedCount;
    }

    /// T at x, and its gradient if asked.
    double at(const Vec3& x, Vec3* gradientAt = nullptr) const {
        const Vec3 y = x - center, hy = hessian * y;
        if (gradientAt) *gradientAt = gradient + hy;
        return value + gradient.dot(y) + 0.5 * y.dot(hy);
    }
};

/// MpuLocalList::sharpPieces for `list` over the model's box: for each of
/// its sharp locals whose crease the model proves away from the box, the
/// piece it takes all over the box (its piece at the centre).
uint32_t mpuResolvedSharpPieces(const MpuField& field, const MpuNumeratorModel& m, const MpuLocalList& list);

/// Taylor's remainder of a model within distance r of its centre, given M3
/// (third) and the errors that do not shrink with r (valueFloor,
/// slopeFloor: rounding, balls bounded directly): value M3 r^3 / 6, slope
/// M3 r^2 / 2, each plus its floor.
struct MpuTaylorRemainder {
    double value, slope;
};
inline MpuTaylorRemainder mpuTaylorRemainder(double third, double r, double valueFloor, double slopeFloor) {
    constexpr double scale = 1 + 1e-9;
    return {third * r * r * r / 6.0 * scale + valueFloor, third * r * r / 2.0 * scale + slopeFloor};
}

/// Locals of one piece laid out for vector sums: the single-piece locals of
/// a tracing cell's list, gathered once for the many models of the boxes
/// carved from it (each sums the same list), or the sharp locals an
/// enclosing model resolved to one piece. Columns hold ball, quadric and
/// curvature; sharp locals not taken as one piece are listed apart.
class MpuLocalColumns {
public:
    enum Column {
        CenterX, CenterY, CenterZ, Radius, InverseRadius2,
        OriginX, OriginY, OriginZ, Axx, Axy, Axz, Ayy, Ayz, Azz, Gx, Gy, Gz, C0,
        Curvature,  ///< MpuField::pieceCurvature
        kColumns
    };

    MpuLocalColumns() = default;
    MpuLocalColumns(const MpuField& field, std::span<const uint32_t> locals) { assign(field, locals); }
    /// The single-piece locals of `locals` (indices into field.locals()) as
    /// columns, the others in sharp(); reuses its storage.
    void assign(const MpuField& field, std::span<const uint32_t> locals);
    /// The sharp locals resolved to one piece for the boxes inside `outer`'s:
    /// those `ancestor` (resolved by a model of a box holding outer's, if
    /// any) holds as columns, and those of `sharp` (its sharp() or, without
    /// it, the list's) whose crease does not cross outer's box, as columns of
    /// the piece each takes all over it. The rest (all, where `outer` lost
    /// count of its creases) go to sharp().
    void assignResolved(const MpuField& field, const MpuLocalColumns* ancestor, std::span<const uint32_t> sharp,
                        const MpuNumeratorModel& outer);

    size_t singleCount() const { return singleCount_; }
    /// Column c: singleCount() values, columns stride() apart.
    const double* column(Column c) const { return data_.data() + size_t(c) * stride_; }
    size_t stride() const { return stride_; }
    /// Sharp locals' indices into field.locals().
    std::span<const uint32_t> sharp() const { return sharp_; }

private:
    void fill(const MpuField& field, std::span<const uint32_t> locals, std::span<const uint8_t> pieces);

    size_t singleCount_ = 0, stride_ = 0;
    std::vector<double> data_;
    std::vector<uint32_t> sharp_, indices_;  ///< indices_: each column's local
    std::vector<uint8_t> pieces_;            ///< each column's piece, from its local's first
};

/// The model of N over `box` from a list of locals that holds every one
/// whose ball reaches the box (others listed are skipped). The box must lie
/// in the field's domain, and the field hold no interpolants. `resolved`,
/// where given, holds the sharp locals of `locals` resolved by a model of
/// a box holding this one (MpuLocalColumns::assignResolved): they are
/// summed and bounded as single pieces, and its sharp() replace those of
/// `locals`.
MpuNumeratorModel fitMpuNumeratorModel(const MpuField& field, const Box3& box, const MpuLocalColumns& locals,
                                       const MpuLocalColumns* resolved = nullptr);

/// The range of value + gradient . y + y^T A y (A symmetric) over
/// |y_k| <= half_k.
Interval quadraticRange(double value, const Vec3& gradient, const Mat3& A, const Vec3& half);

}  // namespace isotrace::geometry
