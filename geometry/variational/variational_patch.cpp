#include "variational_patch.h"

#include <cmath>
#include <limits>

namespace isotrace::geometry {

namespace {

// Monomials of degree <= 4 in three variables, graded: exponents and the
// index of each exponent triple.
struct MonomialTable {
    std::array<std::array<int, 3>, VariationalPatch::kMonomials> exponents{};
    int index[5][5][5]{};
    std::array<double, VariationalPatch::kMonomials> inverseFactorial{};  ///< 1 / (a! b! c!)

    // Ordered for nested Horner evaluation: x outermost, then y, then z.
    MonomialTable() {
        const double factorial[5] = {1, 1, 2, 6, 24};
        int n = 0;
        for (int a = 0; a <= 4; ++a)
            for (int b = 0; a + b <= 4; ++b)
                for (int c = 0; a + b + c <= 4; ++c) {
                    exponents[n] = {a, b, c};
                    index[a][b][c] = n;
                    inverseFactorial[n] = 1.0 / (factorial[a] * factorial[b] * factorial[c]);
                    ++n;
                }
    }
    // The monomial of a multiset of axes, e.g. {0, 0, 2} -> x^2 z.
    template <class... Axes>
    int of(Axes... axes) const {
        int e[3] = {0, 0, 0};
        (++e[axes], ...);
        return index[e[0]][e[1]][e[2]];
    }
};

const MonomialTable& monomials() {
    static const MonomialTable table;
    return table;
}

// Powers h^0..h^4 of each coordinate.
struct Powers {
    double p[3][5];
    explicit Powers(const Vec3& h) {
        for (int k = 0; k < 3; ++k) {
            p[k][0] = 1.0;
            for (int n = 1; n <= 4; ++n) p[k][n] = p[k][n - 1] * h[k];
        }
    }
};

inline double delta(int i, int j) { return i == j ? 1.0 : 0.0; }

// Bound on |d^5/dt^5 |x + t u|^3| * r^2 for unit u (see the header).
constexpr double kFifthDerivative = 12.88;

}  // namespace

std::optional<VariationalPatch> buildVariationalPatch(const VariationalField& field, const Box3& box,
                                                      const PatchOptions& options) {
    if (!field.gradientCenters.empty() || box.isEmpty() || !box.isFinite()) return std::nullopt;
    const MonomialTable& table = monomials();
    VariationalPatch patch;
    patch.box = box;
    const Vec3 x0 = box.center();
    patch.expansionPoint = x0;
    const double s = box.halfDiagonal();
    const double nearRadius = options.nearFactor * s;

    // Sums over the far terms (d = x0 - c, r = |d|), named by the power of r
    // that weights them; each indexed by the monomial d^beta it multiplies.
    constexpr int M = VariationalPatch::kMonomials;
    double r3Sum = 0, rSum = 0;  // sum w r^3, sum w r
    std::array<double, M> byR{}, byInvR{}, byInvR3{}, byInvR5{};  // w r d^b, w/r d^b, w/r^3 d^b, w/r^5 d^b
    double remainderSum = 0;     // sum |w| / (r - s)^2
    double magnitudeSum = 0;     // sum |w| (r + s)^3, for rounding
    for (size_t j = 0; j < field.centers.size(); ++j) {
        const Vec3 d = x0 - field.centers[j];
        const double w = field.weights[j], r = d.norm();
        if (r < nearRadius) {
            patch.near.push_back({field.centers[j], w});
            continue;
        }
        const Powers pw(d);
        const double wr = w * r, w1 = w / r, w3 = w1 / (r * r), w5 = w3 / (r * r);
        r3Sum += wr * r * r;
        rSum += wr;
        for (int n = 0; n < M; ++n) {
            const auto& e = table.exponents[n];
            const int degree = e[0] + e[1] + e[2];
            const double m = pw.p[0][e[0]] * pw.p[1][e[1]] * pw.p[2][e[2]];
            if (degree == 1) byR[n] += wr * m;
            if (degree <= 2) byInvR[n] += w1 * m;
            if (degree == 2 || degree == 3) byInvR3[n] += w3 * m;
            if (degree == 4) byInvR5[n] += w5 * m;
        }
        remainderSum += std::abs(w) / ((r - s) * (r - s));
        magnitudeSum += std::abs(w) * (r + s) * (r + s) * (r + s);
    }

    // Partial derivatives of sum w |x - c|^3 at x0 from those sums:
    //   d_i      = 3 w r d_i
    //   d_ij     = 3 (w r delta_ij + w d_i d_j / r)
    //   d_ijk    = 3 w (delta_ij d_k + delta_ik d_j + delta_jk d_i) / r - 3 w d_i d_j d_k / r^3
    //   d_ijkl   = 3 w (dd + dd + dd) / r - 3 w (delta d d, six ways) / r^3 + 9 w d_i d_j d_k d_l / r^5
    for (int n = 0; n < M; ++n) {
        const auto& e = table.exponents[n];
        int axes[4], k = 0;
        for (int axis = 0; axis < 3; ++axis)
            for (int c = 0; c < e[axis]; ++c) axes[k++] = axis;
        double derivative = 0.0;
        switch (k) {
            case 0: derivative = r3Sum + field.constant + field.linear.dot(x0); break;
            case 1: derivative = 3.0 * byR[n] + field.linear[axes[0]]; break;
            case 2: {
                const int i = axes[0], j = axes[1];
                derivative = 3.0 * (rSum * delta(i, j) + byInvR[n]);
                break;
            }
            case 3: {
                const int i = axes[0], j = axes[1], l = axes[2];
                derivative = 3.0 * (delta(i, j) * byInvR[table.of(l)] + delta(i, l) * byInvR[table.of(j)] +
                                    delta(j, l) * byInvR[table.of(i)]) -
                             3.0 * byInvR3[n];
                break;
            }
            case 4: {
                const int i = axes[0], j = axes[1], l = axes[2], m = axes[3];
                const double pairs = delta(i, j) * delta(l, m) + delta(i, l) * delta(j, m) + delta(i, m) * delta(j, l);
                const double mixed =
                    delta(i, j) * byInvR3[table.of(l, m)] + delta(i, l) * byInvR3[table.of(j, m)] +
                    delta(i, m) * byInvR3[table.of(j, l)] + delta(j, l) * byInvR3[table.of(i, m)] +
                    delta(j, m) * byInvR3[table.of(i, l)] + delta(l, m) * byInvR3[table.of(i, j)];
                derivative = 3.0 * byInvR[0] * pairs - 3.0 * mixed + 9.0 * byInvR5[n];
                break;
            }
        }
        patch.coefficients[n] = derivative * table.inverseFactorial[n];
    }

    // Rounding: every coefficient is a sum of N terms whose sizes the
    // magnitude sum majorises (with room to spare for the Taylor weights).
    const double unitRoundoff = std::numeric_limits<double>::epsilon() / 2;
    const double rounding = 16.0 * double(field.centers.size() + M) * unitRoundoff * magnitudeSum;
    const double s4 = s * s * s * s;
    patch.valueError = kFifthDerivative / 120.0 * s4 * s * remainderSum + rounding;
    patch.gradientError = kFifthDerivative / 24.0 * s4 * remainderSum + 4.0 * rounding / std::max(s, 1e-300);

    // |grad f| over the box: each monomial's gradient bounded by the box's
    // half extents, then the error and the near terms.
    const Vec3 half = 0.5 * box.extent();
    const Powers ph(half);
    double axisBound[3] = {0, 0, 0};
    for (int n = 1; n < M; ++n) {
        const auto& e = table.exponents[n];
        for (int axis = 0; axis < 3; ++axis) {
            if (e[axis] == 0) continue;
            double m = e[axis];
            for (int other = 0; other < 3; ++other) m *= ph.p[other][e[other] - (other == axis ? 1 : 0)];
            axisBound[axis] += std::abs(patch.coefficients[n]) * m;
        }
    }
    double nearGradient = 0.0;
    for (const NearTerm& t : patch.near) {
        const double r = (t.center - x0).norm() + s;
        nearGradient += 3.0 * std::abs(t.weight) * r * r;
    }
    patch.lipschitz = std::sqrt(axisBound[0] * axisBound[0] + axisBound[1] * axisBound[1] +
                                axisBound[2] * axisBound[2]) +
                      patch.gradientError + nearGradient;
    patch.holdsNoZero = std::abs(patch.value(x0)) > patch.lipschitz * s + patch.valueError;
    return patch;
}

std::optional<VariationalPatchGrid> buildVariationalPatchGrid(const VariationalField& field, const Box3& box,
                                                              double tolerance, int maxResolution) {
    VariationalPatchGrid grid;
    grid.box = box;
    for (int resolution = 1;; resolution *= 2) {
        grid.resolution = resolution;
        grid.patches.clear();
        const Vec3 cell = grid.cellExtent();
        bool fineEnough = true;
        for (int k = 0; k < resolution; ++k)
            for (int j = 0; j < resolution; ++j)
                for (int i = 0; i < resolution; ++i) {
                    const Vec3 lower = box.lower + cell.cwiseProduct(Vec3(i, j, k));
                    auto patch = buildVariationalPatch(field, Box3(lower, lower + cell));
                    if (!patch) return std::nullopt;
                    fineEnough = fineEnough && (patch->holdsNoZero || patch->valueError <= tolerance);
                    grid.patches.push_back(std::move(*patch));
                }
        if (fineEnough || 2 * resolution > maxResolution) return grid;
    }
}

namespace {

// The polynomial by nested Horner rules in the table's order: 35
// multiply-adds, unrolled by the compiler (every bound is a constant).
inline double polynomial(const std::array<double, VariationalPatch::kMonomials>& coefficients, const Vec3& h) {
    int n = VariationalPatch::kMonomials;
    double px = 0.0;
    for (int a = 4; a >= 0; --a) {
        double py = 0.0;
        for (int b = 4 - a; b >= 0; --b) {
            double pz = 0.0;
            for (int c = 4 - a - b; c >= 0; --c) pz = pz * h.z() + coefficients[--n];
            py = py * h.y() + pz;
        }
        px = px * h.x() + py;
    }
    return px;
}

}  // namespace

double VariationalPatch::value(const Vec3& x) const {
    double sum = polynomial(coefficients, x - expansionPoint);
    for (const NearTerm& t : near) {
        const double r = (x - t.center).norm();
        sum += t.weight * r * r * r;
    }
    return sum;
}

double VariationalPatch::valueAndGradient(const Vec3& x, Vec3& gradient) const {
    const MonomialTable& table = monomials();
    const Powers p(x - expansionPoint);
    double sum = 0.0;
    Vec3 g = Vec3::Zero();
    for (int n = 0; n < kMonomials; ++n) {
        const auto& e = table.exponents[n];
        const double c = coefficients[n];
        sum += c * p.p[0][e[0]] * p.p[1][e[1]] * p.p[2][e[2]];
        if (e[0]) g.x() += c * e[0] * p.p[0][e[0] - 1] * p.p[1][e[1]] * p.p[2][e[2]];
        if (e[1]) g.y() += c * e[1] * p.p[0][e[0]] * p.p[1][e[1] - 1] * p.p[2][e[2]];
        if (e[2]) g.z() += c * e[2] * p.p[0][e[0]] * p.p[1][e[1]] * p.p[2][e[2] - 1];
    }
    for (const NearTerm& t : near) {
        const Vec3 d = x - t.center;
        const double r = d.norm();
        sum += t.weight * r * r * r;
        g += (3.0 * t.weight * r) * d;
    }
    gradient = g;
    return sum;
}

}  // namespace isotrace::geometry
