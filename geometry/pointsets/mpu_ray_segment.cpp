#include "geometry/pointsets/mpu_ray_segment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "geometry/quadratic_roots.h"
#include "geometry/segment_polynomial.h"

namespace isotrace::geometry {

namespace {

constexpr int kDegree = 8;  // weight (6) times quadric (2)
using Polynomial = Monomials<kDegree>;

// A quadratic in u: the piece's value along x(u) = p0 + u D.
std::array<double, 3> alongSegment(const MpuQuadric& q, const Vec3& p0, const Vec3& D) {
    const Vec3 y = p0 - q.origin, Ay = q.A * y, AD = q.A * D;
    return {q.c0 + q.g.dot(y) + y.dot(Ay), q.g.dot(D) + 2.0 * y.dot(AD), D.dot(AD)};
}

// w(u) Q(u), with w's cube of a quadratic given.
Polynomial weightedPiece(const Monomials<6>& w, const std::array<double, 3>& q) {
    Polynomial p{};
    for (int i = 0; i <= 6; ++i)
        for (int j = 0; j <= 2; ++j) p[i + j] += w[i] * q[j];
    return p;
}

struct PieceChoice {
    double value;
    int index;
};
PieceChoice largerChoice(const PieceChoice& a, const PieceChoice& b) { return a.value >= b.value ? a : b; }
PieceChoice smallerChoice(const PieceChoice& a, const PieceChoice& b) { return a.value <= b.value ? a : b; }

}  // namespace

MpuSegmentRoot firstRootAlongSegment(const MpuField& field, MpuLocalList locals, const Vec3& origin,
                                     const Vec3& direction, double t0, double t1, double tolerance) {
    MpuSegmentRoot result;
    if (!(t1 > t0)) return result;
    // Per-thread scratch: grows to the largest part once, then reused.
    thread_local SegmentPolynomialSum<kDegree> sum;
    sum.clear();
    const Vec3 p0 = origin + t0 * direction, D = (t1 - t0) * direction;
    const double DD = D.squaredNorm();
    // The background's term inside the domain: its weight times its margin.
    sum.addConstant(MpuField::kBackgroundWeight * field.backgroundMargin());
    const std::vector<MpuLocal>& all = field.locals();
    const std::vector<MpuQuadric>& pieces = field.pieces();
    // The list's single-piece locals in vector lanes; the sharp ones here.
    result.localTerms = field.addSinglesAlongSegment(p0, D, locals.singleLocals(), sum);
    const std::span<const uint32_t> others = locals.otherLocals();
    for (size_t position = 0; position < others.size(); ++position) {
        const MpuLocal& l = all[others[position]];
        // s(u) = 1 - |p0 + u D - c|^2 / R^2 = s0 + s1 u + s2 u^2; the ball is
        // s > 0. Most balls listed for a part miss the segment: test R^2 s
        // first, without a division.
        const Vec3 r0 = p0 - l.center;
        const double R2 = l.radius * l.radius, r0D = r0.dot(D);
        const double scaled0 = R2 - r0.squaredNorm();  // R^2 s0
        const double disc = r0D * r0D + DD * scaled0;   // (R^2)^2 (s1^2 - 4 s2 s0) / 4
        if (!(disc > 0.0)) continue;
        // s2 < 0: the ball is between u = (-r0D -+ sqrt(disc)) / DD.
        const double root = std::sqrt(disc);
        const double enter = std::max(0.0, (-r0D - root) / DD), leave = std::min(1.0, (-r0D + root) / DD);
        if (!(enter < leave)) continue;
        const double inverseR2 = 1.0 / R2;
        const double s0 = scaled0 * inverseR2, s1 = -2.0 * r0D * inverseR2, s2 = -DD * inverseR2;
        ++result.localTerms;
        const Monomials<6> w = composeWithQuadratic<3>({0.0, 0.0, 0.0, 1.0}, s0, s1, s2);  // s^3
        // A piece known to be the one taken (the part's box proves it) is
        // summed alone.
        const int known = locals.pieceOf(position);
        if (known >= 0) {
            sum.add(weightedPiece(w, alongSegment(pieces[l.first + known], p0, D)), enter, leave);
            continue;
        }
        // The local's pieces along the segment, and the intervals of u on
        // which each is the one its combination takes.
        std::array<double, 3> q[3];
        const MpuQuadric* piece = &pieces[l.first];
        for (int j = 0; j < l.count; ++j) q[j] = alongSegment(piece[j], p0, D);
        double bounds[9] = {enter};  // enter, up to 3 pairs of crossings, leave
        int boundCount = 1;
        if (l.count > 1)
            for (int i = 0; i < l.count; ++i)
                for (int j = i + 1; j < l.count; ++j)
                    quadraticRootsBetween(q[i][2] - q[j][2], q[i][1] - q[j][1], q[i][0] - q[j][0], enter, leave, bounds,
                                 boundCount);
        for (int i = 2; i < boundCount; ++i)  // insertion sort of at most six crossings
            for (int j = i; j > 1 && bounds[j - 1] > bounds[j]; --j) std::swap(bounds[j - 1], bounds[j]);
        bounds[boundCount] = leave;
        int previousPiece = -1;
        double from = enter;
        for (int k = 0; k < boundCount; ++k) {
            int chosen = 0;
            if (l.count > 1) {
                const double mid = 0.5 * (bounds[k] + bounds[k + 1]);
                PieceChoice v[3];
                for (int i = 0; i < l.count; ++i) v[i] = {q[i][0] + mid * (q[i][1] + mid * q[i][2]), i};
                chosen = combineMpuPieces(l, v, largerChoice, smallerChoice).index;
            }
            // The same piece across a crossing of two others goes on.
            if (previousPiece >= 0 && chosen != previousPiece) {
                sum.add(weightedPiece(w, q[previousPiece]), from, bounds[k]);
                from = bounds[k];
            }
            previousPiece = chosen;
        }
        sum.add(weightedPiece(w, q[previousPiece]), from, leave);
    }
    const SegmentPolynomialSum<kDegree>::Root root = sum.firstRoot(tolerance / (t1 - t0));
    result.pieces = root.pieces;
    if (root.found) {
        result.hit = true;
        result.t = t0 + root.u * (t1 - t0);
    }
    return result;
}

}  // namespace isotrace::geometry
