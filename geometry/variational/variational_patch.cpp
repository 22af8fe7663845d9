#include "geometry/variational/variational_patch.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace isotrace::geometry {

namespace {

// Monomials of degree <= 4 in three variables, ordered for nested Horner
// evaluation: x outermost, then y, then z.
constexpr std::array<std::array<int, 3>, VariationalPatch::kMonomials> kExponents = [] {
    std::array<std::array<int, 3>, VariationalPatch::kMonomials> e{};
    int n = 0;
    for (int a = 0; a <= 4; ++a)
        for (int b = 0; a + b <= 4; ++b)
            for (int c = 0; a + b + c <= 4; ++c) e[n++] = {a, b, c};
    return e;
}();

struct MonomialTable {
    const std::array<std::array<int, 3>, VariationalPatch::kMonomials>& exponents = kExponents;
    int index[5][5][5]{};
    std::array<double, VariationalPatch::kMonomials> inverseFactorial{};  ///< 1 / (a! b! c!)

    // Per monomial n (of degree k, axes sorted): the lower-order sums its
    // Taylor coefficient needs (see the derivative formulas in
    // buildVariationalPatch), so that building a model looks nothing up.
    struct Derivative {
        int degree = 0, axis = 0;  ///< axis: the one of a first-degree monomial
        double delta = 0.0;        ///< delta_ij of a second-degree one
        std::array<int, 6> lower{};
        std::array<double, 6> lowerDelta{};  ///< third: 3 (delta, index); fourth: 6
        double pairs = 0.0;                  ///< fourth degree: the three delta products
    };
    std::array<Derivative, VariationalPatch::kMonomials> derivative{};
    // d/dx_axis and d2/dx_i dx_j of each monomial: a multiplier times a
    // monomial of lower degree.
    struct Reduced {
        int monomial, lower, axis, pair;  ///< pair: 0 xx, 1 xy, 2 xz, 3 yy, 4 yz, 5 zz
        double multiplier;
    };
    std::vector<Reduced> firstPartials, secondPartials;

    MonomialTable() {
        const double factorial[5] = {1, 1, 2, 6, 24};
        for (int n = 0; n < VariationalPatch::kMonomials; ++n) {
            const auto& e = exponents[n];
            index[e[0]][e[1]][e[2]] = n;
            inverseFactorial[n] = 1.0 / (factorial[e[0]] * factorial[e[1]] * factorial[e[2]]);
        }
        auto delta = [](int i, int j) { return i == j ? 1.0 : 0.0; };
        for (int n = 0; n < VariationalPatch::kMonomials; ++n) {
            const auto& e = exponents[n];
            int axes[4], k = 0;
            for (int axis = 0; axis < 3; ++axis)
                for (int c = 0; c < e[axis]; ++c) axes[k++] = axis;
            Derivative& d = derivative[n];
            d.degree = k;
            if (k == 1) d.axis = axes[0];
            if (k == 2) d.delta = delta(axes[0], axes[1]);
            if (k == 3) {
                const int i = axes[0], j = axes[1], l = axes[2];
                d.lower = {of(l), of(j), of(i), 0, 0, 0};
                d.lowerDelta = {delta(i, j), delta(i, l), delta(j, l), 0, 0, 0};
            }
            if (k == 4) {
                const int i = axes[0], j = axes[1], l = axes[2], m = axes[3];
                d.pairs = delta(i, j) * delta(l, m) + delta(i, l) * delta(j, m) + delta(i, m) * delta(j, l);
                d.lower = {of(l, m), of(j, m), of(j, l), of(i, m), of(i, l), of(i, j)};
                d.lowerDelta = {delta(i, j), delta(i, l), delta(i, m), delta(j, l), delta(j, m), delta(l, m)};
            }
            for (int axis = 0; axis < 3; ++axis) {
                if (e[axis] == 0) continue;
                int lower[3] = {e[0], e[1], e[2]};
                --lower[axis];
                firstPartials.push_back({n, index[lower[0]][lower[1]][lower[2]], axis, 0, double(e[axis])});
            }
            int pair = 0;
            for (int i = 0; i < 3; ++i)
                for (int j = i; j < 3; ++j, ++pair) {
                    int lower[3] = {e[0], e[1], e[2]};
                    const double m = lower[i]--;
                    const double m2 = m * lower[j]--;
                    if (m2 == 0 || lower[i] < 0 || lower[j] < 0) continue;
                    secondPartials.push_back({n, index[lower[0]][lower[1]][lower[2]], i, pair, m2});
                }
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


// Bound on |d^5/dt^5 |x + t u|^3| * r^2 for unit u (see the header).
constexpr double kFifthDerivative = 12.88;
// Bound on |d^5/dt^5 psi| * r^3 / |b| for a Hermite term psi = 3 r (b.d):
// 3 (max |a (1 - a^2) (45 - 105 a^2)| + 5 * 3), a the cosine between the
// line and d (the first from D^5 r, the second from 5 (b.u) D^4 r).
constexpr double kHermiteFifthDerivative = 3.0 * (9.882 + 15.0);

template <typename T>
inline T pick(int axis, T x, T y, T z) {
    return axis == 0 ? x : axis == 1 ? y : z;
}

// The partial derivative d^(A,B,C) of r = |d| at d, given 1/r, 1/r^3, 1/r^5
// and 1/r^7 (by induction from d_i r = d_i / r; every Kronecker delta is a
// compile-time constant).
template <int A, int B, int C, typename T>
inline T radialDerivative(T x, T y, T z, T r, T i1, T i3, T i5, T i7) {
    constexpr int n = A + B + C;
    static constexpr std::array<int, 4> ax = [] {
        std::array<int, 4> a{0, 0, 0, 0};
        int k = 0;
        for (int i = 0; i < A; ++i) a[k++] = 0;
        for (int i = 0; i < B; ++i) a[k++] = 1;
        for (int i = 0; i < C; ++i) a[k++] = 2;
        return a;
    }();
    auto d = [&](int k) { return pick(ax[k], x, y, z); };
    auto delta = [](int i, int j) { return ax[i] == ax[j] ? 1.0 : 0.0; };
    if constexpr (n == 0) {
        return r;
    } else if constexpr (n == 1) {
        return d(0) * i1;
    } else if constexpr (n == 2) {
        return delta(0, 1) * i1 - d(0) * d(1) * i3;
    } else if constexpr (n == 3) {
        return -(delta(0, 1) * d(2) + delta(0, 2) * d(1) + delta(1, 2) * d(0)) * i3 + 3.0 * d(0) * d(1) * d(2) * i5;
    } else {
        const double pairs = delta(0, 1) * delta(2, 3) + delta(0, 2) * delta(1, 3) + delta(0, 3) * delta(1, 2);
        const T mixed = delta(0, 1) * d(2) * d(3) + delta(0, 2) * d(1) * d(3) + delta(0, 3) * d(1) * d(2) +
                             delta(1, 2) * d(0) * d(3) + delta(1, 3) * d(0) * d(2) + delta(2, 3) * d(0) * d(1);
        return -pairs * i3 + 3.0 * mixed * i5 - 15.0 * d(0) * d(1) * d(2) * d(3) * i7;
    }
}

template <int K, typename T>
inline T power(T x) {
    if constexpr (K == 0) return T{} + 1.0;
    else if constexpr (K == 1) return x;
    else return x * power<K - 1>(x);
}

// Per-centre quantities, one array each so that every sum below is a
// vector loop. Kept per thread: building a model allocates nothing after
// the first.
struct Scratch {
    std::vector<double> dx, dy, dz, r;
    std::vector<double> rWeight;        // w r (every term)
    std::vector<double> hessianWeight;  // w / r (every term; 0 at r = 0)
    std::vector<double> farInvR, farInvR3, farInvR5;  // w / r^k, far terms only
    std::vector<uint8_t> isNear;  // 1 for a near term, padded to whole words with 0

    void resize(size_t n) {
        for (auto* v : {&dx, &dy, &dz, &r, &rWeight, &hessianWeight, &farInvR, &farInvR3, &farInvR5}) v->resize(n);
        // The flags of [0, n) are written for every model; the padding stays 0.
        isNear.resize((n + 7) / 8 * 8);
        std::fill(isNear.begin() + n, isNear.end(), 0);
    }
};

// Per Hermite term: d = x0 - c, r, b (the negated gradient weight) and
// s = b.d for every term (the orders 0 and 1 the near ones share), and the
// same masked to far terms with inverse powers of r safe at near ones.
struct HermiteScratch {
    std::vector<double> dx, dy, dz, r, inverseR, s, bx, by, bz;
    std::vector<double> farR, farInvR, farInvR3, farInvR5, farInvR7, farS, farBx, farBy, farBz;
    std::vector<double> remainder, innerRemainder, magnitude;  // |b| / (r - s)^3, / (r - s/2)^3 (far), 3 |b| (r + s)^2

    void resize(size_t n) {
        for (auto* v : {&dx, &dy, &dz, &r, &inverseR, &s, &bx, &by, &bz, &farR, &farInvR, &farInvR3, &farInvR5,
                        &farInvR7, &farS, &farBx, &farBy, &farBz, &remainder, &innerRemainder, &magnitude})
            v->resize(n);
    }
};

inline double plainSum(const std::vector<double>& v) {
    double sum = 0.0;
    const double* p = v.data();
    const size_t n = v.size();
#pragma omp simd reduction(+ : sum)
    for (size_t j = 0; j < n; ++j) sum += p[j];
    return sum;
}

// The sums the Taylor coefficients need, named by the power of r that
// weights them; each indexed by the monomial d^beta it multiplies.
struct TermSums {
    std::array<double, VariationalPatch::kMonomials> byR{}, byInvR{}, byInvR3{}, byInvR5{};
};

// sum_j weight_j d_j^alpha for every monomial alpha in I..., in one pass
// over the centres: per-monomial passes each reread the four arrays and
// made the sums three quarters of a model's cost. Eight lanes at a time in
// GNU vector types (AVX-512 where built for it), the rest one by one. Not
// geometry/lanes.h's std::experimental::simd: with it the same sums built
// the hand's models 6% slower, its Hermite fit's 23% slower (GCC 12).
using Lanes = double __attribute__((vector_size(64)));
constexpr size_t kLanes = sizeof(Lanes) / sizeof(double);

template <size_t... I, typename T>
inline void monomialTerms(T* acc, T w, T x, T y, T z, std::index_sequence<I...>) {
    size_t k = 0;
    ((acc[k++] += w * power<kExponents[I][0]>(x) * power<kExponents[I][1]>(y) * power<kExponents[I][2]>(z)), ...);
}

// K sums over n terms: term(acc, at) adds term j's K values to acc, reading
// the term's entry of an array p as at(p). Eight terms at a time in lanes,
// the rest one by one, then the lanes added up.
template <size_t K, class Term>
std::array<double, K> laneSums(size_t n, Term term) {
    Lanes acc[K] = {};
    size_t j = 0;
    for (; j + kLanes <= n; j += kLanes)
        term(acc, [j](const double* p) {
            Lanes v;
            std::memcpy(&v, p + j, sizeof(Lanes));
            return v;
        });
    double rest[K] = {};
    for (; j < n; ++j) term(rest, [j](const double* p) { return p[j]; });
    std::array<double, K> sums;
    for (size_t k = 0; k < K; ++k) {
        sums[k] = rest[k];
        for (size_t lane = 0; lane < kLanes; ++lane) sums[k] += acc[k][lane];
    }
    return sums;
}

template <size_t... I>
void moments(const std::vector<double>& weight, const Scratch& s, std::array<double, VariationalPatch::kMonomials>& out,
             std::index_sequence<I...> monomials) {
    const double *w = weight.data(), *x = s.dx.data(), *y = s.dy.data(), *z = s.dz.data();
    const auto sums = laneSums<sizeof...(I)>(weight.size(), [&](auto* acc, auto at) {
        monomialTerms(acc, at(w), at(x), at(y), at(z), monomials);
    });
    size_t k = 0;
    ((out[I] = sums[k++]), ...);
}

// The monomials of one degree, as indices into kExponents.
template <int Degree>
constexpr auto monomialsOfDegree() {
    constexpr size_t count = (Degree + 1) * (Degree + 2) / 2;
    std::array<size_t, count> indices{};
    size_t k = 0;
    for (size_t n = 0; n < kExponents.size(); ++n)
        if (kExponents[n][0] + kExponents[n][1] + kExponents[n][2] == Degree) indices[k++] = n;
    return indices;
}

template <int Degree, size_t... K>
constexpr auto degreeSequence(std::index_sequence<K...>) {
    constexpr auto indices = monomialsOfDegree<Degree>();
    return std::index_sequence<indices[K]...>();
}

template <int Degree>
constexpr auto degreeMonomials() {
    return degreeSequence<Degree>(std::make_index_sequence<(Degree + 1) * (Degree + 2) / 2>());
}

void accumulateMonomials(const Scratch& s, TermSums& out) {
    moments(s.rWeight, s, out.byR, degreeMonomials<1>());
    moments(s.farInvR, s, out.byInvR, degreeMonomials<1>());
    moments(s.hessianWeight, s, out.byInvR, degreeMonomials<2>());
    moments(s.farInvR3, s, out.byInvR3, degreeMonomials<2>());
    moments(s.farInvR3, s, out.byInvR3, degreeMonomials<3>());
    moments(s.farInvR5, s, out.byInvR5, degreeMonomials<4>());
}

// d^alpha of 3 r (b.d) for the monomial alpha = I: by Leibniz with s = b.d
// linear, 3 (s d^alpha r + sum_i alpha_i b_i d^(alpha - e_i) r); the 3 is
// applied to the sums.
template <size_t I, typename T>
inline T hermiteTerm(T x, T y, T z, T r, T i1, T i3, T i5, T i7, T s, T bx, T by, T bz) {
    constexpr int a = kExponents[I][0], b = kExponents[I][1], c = kExponents[I][2];
    T term = s * radialDerivative<a, b, c>(x, y, z, r, i1, i3, i5, i7);
    if constexpr (a > 0) term += a * bx * radialDerivative<a - 1, b, c>(x, y, z, r, i1, i3, i5, i7);
    if constexpr (b > 0) term += b * by * radialDerivative<a, b - 1, c>(x, y, z, r, i1, i3, i5, i7);
    if constexpr (c > 0) term += c * bz * radialDerivative<a, b, c - 1>(x, y, z, r, i1, i3, i5, i7);
    return term;
}

// The Hermite terms' derivatives for every monomial in I... (all of one
// degree) in one pass over the terms, as `moments` does for the r^3 ones.
// Orders 0 and 1 sum every term, higher orders the far ones.
template <size_t... I>
void hermiteDerivatives(const HermiteScratch& q, std::array<double, VariationalPatch::kMonomials>& out,
                        std::index_sequence<I...>) {
    constexpr size_t K = sizeof...(I);
    constexpr size_t first[] = {I...};
    constexpr int degree = kExponents[first[0]][0] + kExponents[first[0]][1] + kExponents[first[0]][2];
    constexpr bool all = degree <= 1;
    const double *x = q.dx.data(), *y = q.dy.data(), *z = q.dz.data();
    const double *r = all ? q.r.data() : q.farR.data(), *i1 = all ? q.inverseR.data() : q.farInvR.data();
    const double *i3 = q.farInvR3.data(), *i5 = q.farInvR5.data(), *i7 = q.farInvR7.data();
    const double *sv = all ? q.s.data() : q.farS.data(), *bx = all ? q.bx.data() : q.farBx.data(),
                 *by = all ? q.by.data() : q.farBy.data(), *bz = all ? q.bz.data() : q.farBz.data();
    const auto sums = laneSums<K>(q.dx.size(), [&](auto* acc, auto at) {
        size_t k = 0;
        ((acc[k++] += hermiteTerm<I>(at(x), at(y), at(z), at(r), at(i1), at(i3), at(i5), at(i7), at(sv), at(bx), at(by),
                                     at(bz))),
         ...);
    });
    size_t k = 0;
    ((out[I] = 3.0 * sums[k++]), ...);
}

void accumulateHermiteMonomials(const HermiteScratch& q, std::array<double, VariationalPatch::kMonomials>& out) {
    hermiteDerivatives(q, out, degreeMonomials<0>());
    hermiteDerivatives(q, out, degreeMonomials<1>());
    hermiteDerivatives(q, out, degreeMonomials<2>());
    hermiteDerivatives(q, out, degreeMonomials<3>());
    hermiteDerivatives(q, out, degreeMonomials<4>());
}

// Near terms enter the polynomial up to second order only (their third
// derivative jumps at their centre) and are corrected exactly when the
// model is evaluated; far terms enter it to fourth order. Sums over the r^3
// terms about x0 for a box of half-diagonal s; the near terms go to `patch`.
struct RadialTermSums {
    size_t count = 0;
    double r3 = 0.0, r = 0.0;  ///< sum w r^3 and sum w r
    TermSums moments;
    double remainder = 0.0, innerRemainder = 0.0, magnitude = 0.0;  ///< for the error bounds
};

RadialTermSums sumRadialTerms(const VariationalField& field, const Vec3& x0, double s, VariationalPatch& patch) {
    const double nearRadius = kNearFactor * s;
    thread_local Scratch scratch;
    const size_t n = field.centers.size();
    scratch.resize(n);
    const double *cx = field.centers.x(), *cy = field.centers.y(), *cz = field.centers.z();
    const double* w = field.weights.data();
    // Sums that need no moment are taken in the same pass; one reciprocal
    // serves every power of 1 / r.
    RadialTermSums sums;
    sums.count = n;
    double remainderSum = 0.0, innerRemainderSum = 0.0, magnitudeSum = 0.0;
    {
        Scratch& q = scratch;
#pragma omp simd reduction(+ : remainderSum, innerRemainderSum, magnitudeSum)
        for (size_t j = 0; j < n; ++j) {
            const double dx = x0.x() - cx[j], dy = x0.y() - cy[j], dz = x0.z() - cz[j];
            const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
            const bool far = r >= nearRadius;
            const double wFar = far ? w[j] : 0.0;
            const double inv = r > 0 ? 1.0 / r : 0.0, inv2 = inv * inv;
            q.dx[j] = dx;
            q.dy[j] = dy;
            q.dz[j] = dz;
            q.r[j] = r;
            q.rWeight[j] = w[j] * r;
            q.hessianWeight[j] = w[j] * inv;
            q.farInvR[j] = wFar * inv;
            q.farInvR3[j] = wFar * inv * inv2;
            q.farInvR5[j] = wFar * inv * inv2 * inv2;
            // Far centres are at least 1.5 s from x0, so both gaps are positive.
            const double gap = far ? r - s : 1.0, innerGap = far ? r - 0.5 * s : 1.0;
            remainderSum += std::abs(wFar) / (gap * gap);
            innerRemainderSum += std::abs(wFar) / (innerGap * innerGap);
            magnitudeSum += std::abs(w[j]) * (r + s) * (r + s) * (r + s);
        }
    }
    // The coefficients' own sums go through lanes, as the moments do, so
    // that each term passes through a known number of additions (their
    // rounding below), whatever the compiler makes of a reduction.
    const auto [r3Sum, rSum, farInvRSum] = laneSums<3>(n, [&](auto* acc, auto at) {
        const auto rw = at(scratch.rWeight.data()), r = at(scratch.r.data());
        acc[0] += rw * r * r;
        acc[1] += rw;
        acc[2] += at(scratch.farInvR.data());
    });
    // Near centres are a handful of thousands: their flags are read eight
    // at a time, and only a word that holds one is looked at flag by flag.
    // Through plain pointers: a thread_local's vector read in the loop is
    // looked up again after every push_back (a fifth of a model's cost).
    uint8_t* isNear = scratch.isNear.data();
    const double* distance = scratch.r.data();
#pragma omp simd
    for (size_t j = 0; j < n; ++j) isNear[j] = distance[j] < nearRadius;
    for (size_t block = 0; block < n; block += 8) {
        uint64_t word;
        std::memcpy(&word, isNear + block, sizeof word);
        if (word == 0) continue;
        for (size_t j = block; j < std::min(n, block + 8); ++j)
            if (isNear[j]) {
                const double r = distance[j];
                patch.near.push_back({field.centers[j], w[j], r, r > 0 ? 1.0 / r : 0.0});
            }
    }
    sums.r3 = r3Sum;
    sums.r = rSum;
    sums.moments.byInvR[0] = farInvRSum;
    accumulateMonomials(scratch, sums.moments);
    sums.remainder = remainderSum;
    sums.innerRemainder = innerRemainderSum;
    sums.magnitude = magnitudeSum;
    return sums;
}

// The same for the Hermite (gradient) terms, whose near ones are those
// within kHermiteNearFactor half-diagonals.
struct HermiteTermSums {
    size_t count = 0;
    std::array<double, VariationalPatch::kMonomials> monomials{};  ///< their Taylor derivatives by monomial
    double remainder = 0.0, innerRemainder = 0.0, magnitude = 0.0;
};

HermiteTermSums sumHermiteTerms(const VariationalField& field, const Vec3& x0, double s, VariationalPatch& patch) {
    const double hermiteNearRadius = kHermiteNearFactor * s;
    thread_local HermiteScratch hermite;
    const size_t nh = field.gradientCenters.size();
    hermite.resize(nh);
    HermiteTermSums sums;
    sums.count = nh;
    if (nh > 0) {
        HermiteScratch& q = hermite;
        const double* hc = field.gradientCenters[0].data();
        const double* hw = field.gradientWeights[0].data();
#pragma omp simd
        for (size_t j = 0; j < nh; ++j) {
            const double dx = x0.x() - hc[3 * j], dy = x0.y() - hc[3 * j + 1], dz = x0.z() - hc[3 * j + 2];
            const double bx = -hw[3 * j], by = -hw[3 * j + 1], bz = -hw[3 * j + 2];
            const double r = std::sqrt(dx * dx + dy * dy + dz * dz), sv = bx * dx + by * dy + bz * dz;
            const double bNorm = std::sqrt(bx * bx + by * by + bz * bz);
            const bool far = r >= hermiteNearRadius;
            const double rFar = far ? r : 1.0, inv = 1.0 / rFar, inv2 = inv * inv, mask = far ? 1.0 : 0.0;
            q.dx[j] = dx, q.dy[j] = dy, q.dz[j] = dz, q.r[j] = r;
            q.inverseR[j] = r > 0 ? 1.0 / r : 0.0;
            q.s[j] = sv, q.bx[j] = bx, q.by[j] = by, q.bz[j] = bz;
            q.farR[j] = rFar;
            q.farInvR[j] = inv, q.farInvR3[j] = inv * inv2, q.farInvR5[j] = inv * inv2 * inv2,
            q.farInvR7[j] = inv * inv2 * inv2 * inv2;
            q.farS[j] = mask * sv, q.farBx[j] = mask * bx, q.farBy[j] = mask * by, q.farBz[j] = mask * bz;
            const double gap = far ? r - s : 1.0, innerGap = far ? r - 0.5 * s : 1.0;
            q.remainder[j] = mask * bNorm / (gap * gap * gap);
            q.innerRemainder[j] = mask * bNorm / (innerGap * innerGap * innerGap);
            q.magnitude[j] = 3.0 * bNorm * (r + s) * (r + s);
        }
        for (size_t j = 0; j < nh; ++j) {
            if (q.r[j] >= hermiteNearRadius) continue;
            const Vec3 d(q.dx[j], q.dy[j], q.dz[j]), b(q.bx[j], q.by[j], q.bz[j]);
            const double r = q.r[j], sv = q.s[j];
            patch.nearHermite.push_back({field.gradientCenters[j], b, 3.0 * r * sv,
                                         r > 0 ? Vec3(3.0 * (sv / r * d + r * b)) : Vec3::Zero()});
        }
        accumulateHermiteMonomials(q, sums.monomials);
        sums.remainder = plainSum(q.remainder);
        sums.innerRemainder = plainSum(q.innerRemainder);
        sums.magnitude = plainSum(q.magnitude);
    }

    return sums;
}

// The Taylor coefficients at x0 from the sums.
void setCoefficients(const VariationalField& field, const Vec3& x0, const RadialTermSums& radial,
                     const HermiteTermSums& hermite, VariationalPatch& patch) {
    constexpr int M = VariationalPatch::kMonomials;
    const MonomialTable& table = monomials();
    const double r3Sum = radial.r3, rSum = radial.r;
    const auto &byR = radial.moments.byR, &byInvR = radial.moments.byInvR, &byInvR3 = radial.moments.byInvR3,
               &byInvR5 = radial.moments.byInvR5;
    const auto& hermiteSums = hermite.monomials;
    // Partial derivatives of sum w |x - c|^3 at x0 from those sums:
    //   d_i      = 3 w r d_i
    //   d_ij     = 3 (w r delta_ij + w d_i d_j / r)
    //   d_ijk    = 3 w (delta_ij d_k + delta_ik d_j + delta_jk d_i) / r - 3 w d_i d_j d_k / r^3
    //   d_ijkl   = 3 w (dd + dd + dd) / r - 3 w (delta d d, six ways) / r^3 + 9 w d_i d_j d_k d_l / r^5
    for (int n = 0; n < M; ++n) {
        const MonomialTable::Derivative& d = table.derivative[n];
        double derivative = 0.0;
        switch (d.degree) {
            case 0: derivative = r3Sum + field.constant + field.linear.dot(x0); break;
            case 1: derivative = 3.0 * byR[n] + field.linear[d.axis]; break;
            case 2: derivative = 3.0 * (rSum * d.delta + byInvR[n]); break;
            case 3:
                derivative = 3.0 * (d.lowerDelta[0] * byInvR[d.lower[0]] + d.lowerDelta[1] * byInvR[d.lower[1]] +
                                    d.lowerDelta[2] * byInvR[d.lower[2]]) -
                             3.0 * byInvR3[n];
                break;
            case 4: {
                double mixed = 0.0;
                for (int q = 0; q < 6; ++q) mixed += d.lowerDelta[q] * byInvR3[d.lower[q]];
                derivative = 3.0 * byInvR[0] * d.pairs - 3.0 * mixed + 9.0 * byInvR5[n];
                break;
            }
        }
        patch.coefficients[n] = (derivative + hermiteSums[n]) * table.inverseFactorial[n];
    }
}

// Bounds on the model's errors over its box of half-diagonal s, from the
// far terms' fifth derivatives (Taylor's remainder) and the coefficients'
// rounding.
void setTaylorErrors(double s, const RadialTermSums& radial, const HermiteTermSums& hermite, VariationalPatch& patch) {
    constexpr int M = VariationalPatch::kMonomials;
    // Rounding: every coefficient is a sum of terms whose sizes the
    // magnitude sum majorises (with room to spare for the Taylor weights),
    // each term rounded in at most M operations and then in the additions
    // of laneSums: its lane's share of the terms, or the scalar rest, and
    // the lanes' total.
    const double unitRoundoff = std::numeric_limits<double>::epsilon() / 2;
    auto additions = [](size_t terms) { return terms / kLanes + 2 * kLanes; };
    const double rounding = 16.0 * double(additions(radial.count) + additions(hermite.count) + M) * unitRoundoff *
                            (radial.magnitude + hermite.magnitude);
    const double s4 = s * s * s * s;
    // Bound on the fifth directional derivative of the far terms' sum, with
    // each term's r at its nearest to the box (and to the inner ball).
    const double fifth = kFifthDerivative * radial.remainder + kHermiteFifthDerivative * hermite.remainder;
    patch.fifthDerivative = fifth;
    patch.innerFifthDerivative =
        kFifthDerivative * radial.innerRemainder + kHermiteFifthDerivative * hermite.innerRemainder;
    patch.coefficientRounding = rounding;
    patch.halfDiagonal = s;
    patch.gradientError = fifth / 24.0 * s4 + 4.0 * rounding / std::max(s, 1e-300);
    patch.hessianError = fifth / 6.0 * s * s * s + 12.0 * rounding / std::max(s * s, 1e-300);
}

// What the model is worth over its box: its gradient and curvature bounds,
// the noise of evaluating it, its value error and range, and the plane and
// band of its linear part.
void setBoundsOverBox(const Box3& box, double s, VariationalPatch& patch) {
    constexpr int M = VariationalPatch::kMonomials;
    const MonomialTable& table = monomials();
    const double unitRoundoff = std::numeric_limits<double>::epsilon() / 2;
    const double s4 = s * s * s * s;
    // |grad f| over the box: each monomial's gradient bounded by the box's
    // half extents, then the error and the near terms.
    const Vec3 half = 0.5 * box.extent();
    const Powers ph(half);
    std::array<double, M> halfPower;  // each monomial at the box's half extents
    for (int n = 0; n < M; ++n) {
        const auto& e = table.exponents[n];
        halfPower[n] = ph.p[0][e[0]] * ph.p[1][e[1]] * ph.p[2][e[2]];
    }
    double axisBound[3] = {0, 0, 0};
    for (const MonomialTable::Reduced& r : table.firstPartials)
        axisBound[r.axis] += std::abs(patch.coefficients[r.monomial]) * r.multiplier * halfPower[r.lower];
    // A near term's correction w (|x - c|^3 - its quadratic Taylor
    // polynomial) is at most |w| |h|^3, its gradient 3 |w| |h|^2 (|D^3 r^3| <= 6).
    // A near Hermite term's correction (psi less its first-order Taylor
    // polynomial) is at most 4.5 |b| |h|^2, its gradient 9 |b| |h|.
    double nearWeight = 0.0, nearHermiteWeight = 0.0;
    for (const NearTerm& t : patch.near) nearWeight += std::abs(t.weight);
    for (const HermiteNearTerm& t : patch.nearHermite) nearHermiteWeight += t.direction.norm();
    const double polynomialGradient =
        std::sqrt(axisBound[0] * axisBound[0] + axisBound[1] * axisBound[1] + axisBound[2] * axisBound[2]);
    // ||D^2 model||: each second partial of the polynomial bounded
    // monomial by monomial, the matrix of bounds' Frobenius norm bounding
    // the operator norm; a near r^3 term's correction changes its Hessian
    // by at most 6 |w| |h| (|D^3 r^3| <= 6), a Hermite one's is at most 9 |b|.
    double secondBound[6] = {};  // xx, xy, xz, yy, yz, zz
    for (const MonomialTable::Reduced& r : table.secondPartials)
        secondBound[r.pair] += std::abs(patch.coefficients[r.monomial]) * r.multiplier * halfPower[r.lower];
    double frobenius = 0.0;
    for (int pair = 0; pair < 6; ++pair)
        frobenius += (pair == 0 || pair == 3 || pair == 5 ? 1.0 : 2.0) * secondBound[pair] * secondBound[pair];
    patch.curvature = std::sqrt(frobenius) + 6.0 * nearWeight * s + 9.0 * nearHermiteWeight;
    patch.lipschitz =
        polynomialGradient + patch.gradientError + 3.0 * nearWeight * s * s + 9.0 * nearHermiteWeight * s;
    double polynomialSpread = 0.0, linearSpread = 0.0;
    for (int m = 1; m < M; ++m) {
        polynomialSpread += std::abs(patch.coefficients[m]) * halfPower[m];
        const auto& e = table.exponents[m];
        if (e[0] + e[1] + e[2] == 1) linearSpread += std::abs(patch.coefficients[m]) * halfPower[m];
    }
    // Evaluating the model rounds each of its terms; a near term's two
    // parts are each at most |w| (r0 + s)^3.
    double nearMagnitude = 0.0;
    for (const NearTerm& t : patch.near) nearMagnitude += std::abs(t.weight) * std::pow(t.distance + s, 3);
    for (const HermiteNearTerm& t : patch.nearHermite) {
        const double reach = (patch.expansionPoint - t.center).norm() + s;
        nearMagnitude += 3.0 * t.direction.norm() * reach * reach;
    }
    patch.evaluationNoise = 64.0 * unitRoundoff * (std::abs(patch.coefficients[0]) + polynomialSpread + 2.0 * nearMagnitude);
    patch.valueError = patch.fifthDerivative / 120.0 * s4 * s + patch.coefficientRounding + patch.evaluationNoise;
    // Each gradient component sums terms at most degree / s times the value's.
    patch.gradientNoise = 4.0 * patch.evaluationNoise / std::max(s, 1e-300);
    const double spread = polynomialSpread + nearWeight * s * s * s + 4.5 * nearHermiteWeight * s * s + patch.valueError;
    patch.range = {patch.coefficients[0] - spread, patch.coefficients[0] + spread};
    // The same without the linear monomials, which the plane keeps exactly
    // (a margin for rounding the plane's value along a ray).
    patch.planeSlope = Vec3(patch.coefficients[table.index[1][0][0]], patch.coefficients[table.index[0][1][0]],
                            patch.coefficients[table.index[0][0][1]]);
    patch.planeBand = (spread - linearSpread) + 16.0 * unitRoundoff * (std::abs(patch.coefficients[0]) + linearSpread);
    patch.holdsNoZero = !patch.range.containsZero();
}

}  // namespace

std::optional<VariationalPatch> buildVariationalPatch(const VariationalField& field, const Box3& box) {
    if (box.isEmpty() || !box.isFinite()) return std::nullopt;
    VariationalPatch patch;
    patch.box = box;
    const Vec3 x0 = box.center();
    patch.expansionPoint = x0;
    const double s = box.halfDiagonal();
    const RadialTermSums radial = sumRadialTerms(field, x0, s, patch);
    const HermiteTermSums hermite = sumHermiteTerms(field, x0, s, patch);
    setCoefficients(field, x0, radial, hermite, patch);
    setTaylorErrors(s, radial, hermite, patch);
    setBoundsOverBox(box, s, patch);
    return patch;
}

namespace {

// Splits `box` until its models are fine enough, appending the leaves' models
// that may hold surface. A parent's model that proves a child box empty
// spares building the child's.
bool collectSurfaceModels(const VariationalField& field, const Box3& box, double tolerance, int depthLeft,
                          const VariationalPatch* parent, std::vector<VariationalPatch>& out) {
    if (parent) {
        if (!parent->rangeOver(box).containsZero()) return true;
    }
    auto patch = buildVariationalPatch(field, box);
    if (!patch) return false;
    if (patch->holdsNoZero) return true;
    if (patch->valueError <= tolerance || depthLeft == 0) {
        out.push_back(std::move(*patch));
        return true;
    }
    for (int i = 0; i < 8; ++i)
        if (!collectSurfaceModels(field, box.octant(i), tolerance, depthLeft - 1, &*patch, out))
            return false;
    return true;
}

}  // namespace

std::optional<std::vector<VariationalPatch>> buildSurfaceModels(const VariationalField& field, const Box3& box,
                                                               double tolerance, int maxDepth) {
    std::vector<VariationalPatch> models;
    if (!collectSurfaceModels(field, box, tolerance, maxDepth, nullptr, models)) return std::nullopt;
    return models;
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

// w (|x - c|^3 - q(h)), q the quadratic Taylor polynomial of |x - c|^3 at
// the expansion point x0 = x - h, with d0 = x0 - c, r0 = |d0|:
//   q(h) = r0^3 + 3 r0 d0.h + 3/2 (r0 |h|^2 + (d0.h)^2 / r0).
inline double nearCorrection(const NearTerm& t, const Vec3& x, const Vec3& h) {
    const Vec3 d = x - t.center, d0 = d - h;
    const double r = d.norm(), r0 = t.distance, dh = d0.dot(h);
    const double q = r0 * r0 * r0 + 3.0 * r0 * dh + 1.5 * (r0 * h.squaredNorm() + dh * dh * t.inverseDistance);
    return t.weight * (r * r * r - q);
}

// 3 |d| (b.d) less its value and gradient at the expansion point.
inline double nearHermiteCorrection(const HermiteNearTerm& t, const Vec3& x, const Vec3& h) {
    const Vec3 d = x - t.center;
    return 3.0 * d.norm() * t.direction.dot(d) - t.valueAtExpansion - t.gradientAtExpansion.dot(h);
}

double VariationalPatch::value(const Vec3& x) const {
    const Vec3 h = x - expansionPoint;
    double sum = polynomial(coefficients, h);
    for (const NearTerm& t : near) sum += nearCorrection(t, x, h);
    for (const HermiteNearTerm& t : nearHermite) sum += nearHermiteCorrection(t, x, h);
    return sum;
}

namespace {

// The polynomial and its derivative along d, by the same nested Horner rules
// on dual numbers (v, v'): (v, v') (h, d) = (v h, v' h + v d).
inline double polynomialAndSlope(const std::array<double, VariationalPatch::kMonomials>& coefficients, const Vec3& h,
                                 const Vec3& d, double& slope) {
    int n = VariationalPatch::kMonomials;
    double px = 0.0, dpx = 0.0;
    for (int a = 4; a >= 0; --a) {
        double py = 0.0, dpy = 0.0;
        for (int b = 4 - a; b >= 0; --b) {
            double pz = 0.0, dpz = 0.0;
            for (int c = 4 - a - b; c >= 0; --c) {
                dpz = dpz * h.z() + pz * d.z();
                pz = pz * h.z() + coefficients[--n];
            }
            dpy = dpy * h.y() + py * d.y() + dpz;
            py = py * h.y() + pz;
        }
        dpx = dpx * h.x() + px * d.x() + dpy;
        px = px * h.x() + py;
    }
    slope = dpx;
    return px;
}

}  // namespace

double VariationalPatch::fifthDerivativeWithin(double reach) const {
    return reach <= 0.5 * halfDiagonal ? innerFifthDerivative : fifthDerivative;
}

double VariationalPatch::valueErrorWithin(double reach) const {
    if (!(reach < halfDiagonal)) return valueError;
    const double r2 = reach * reach;
    return std::min(valueError,
                    fifthDerivativeWithin(reach) / 120.0 * r2 * r2 * reach + coefficientRounding + evaluationNoise);
}

double VariationalPatch::gradientErrorWithin(double reach) const {
    if (!(reach < halfDiagonal)) return gradientError;
    const double r2 = reach * reach;
    return std::min(gradientError, fifthDerivativeWithin(reach) / 24.0 * r2 * r2 + 4.0 * coefficientRounding / halfDiagonal);
}

Interval VariationalPatch::rangeOver(const Box3& part) const {
    Vec3 gradient;
    const double centre = valueAndGradient(part.center(), gradient), reach = part.halfDiagonal();
    const double spread =
        std::min(lipschitz * reach, gradient.norm() * reach + 0.5 * curvature * reach * reach) + valueError;
    return {centre - spread, centre + spread};
}

double VariationalPatch::valueAndSlope(const Vec3& x, const Vec3& direction, double& slope) const {
    const Vec3 h = x - expansionPoint;
    double sum = polynomialAndSlope(coefficients, h, direction, slope);
    for (const NearTerm& t : near) {
        sum += nearCorrection(t, x, h);
        const Vec3 d = x - t.center, d0 = d - h;
        const double r = d.norm(), r0 = t.distance;
        slope += t.weight * 3.0 *
                 (r * d.dot(direction) - r0 * d0.dot(direction) -
                  (r0 * h.dot(direction) + d0.dot(h) * t.inverseDistance * d0.dot(direction)));
    }
    for (const HermiteNearTerm& t : nearHermite) {
        sum += nearHermiteCorrection(t, x, h);
        const Vec3 d = x - t.center;
        const double r = d.norm();
        if (r > 0) slope += 3.0 * (t.direction.dot(d) / r * d.dot(direction) + r * t.direction.dot(direction));
        slope -= t.gradientAtExpansion.dot(direction);
    }
    return sum;
}

double VariationalPatch::valueAndGradient(const Vec3& x, Vec3& gradient) const {
    const MonomialTable& table = monomials();
    const Vec3 h = x - expansionPoint;
    const Powers p(h);
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
        sum += nearCorrection(t, x, h);
        // grad q = 3 r0 d0 + 3 (r0 h + (d0.h) d0 / r0)
        const Vec3 d = x - t.center, d0 = d - h;
        const double r = d.norm(), r0 = t.distance;
        g += t.weight * (3.0 * r * d - 3.0 * r0 * d0 - 3.0 * (r0 * h + d0.dot(h) * t.inverseDistance * d0));
    }
    for (const HermiteNearTerm& t : nearHermite) {
        sum += nearHermiteCorrection(t, x, h);
        // grad 3 r (b.d) = 3 ((b.d) d / r + r b)
        const Vec3 d = x - t.center;
        const double r = d.norm();
        if (r > 0) g += 3.0 * (t.direction.dot(d) / r * d + r * t.direction);
        g -= t.gradientAtExpansion;
    }
    gradient = g;
    return sum;
}

}  // namespace isotrace::geometry
