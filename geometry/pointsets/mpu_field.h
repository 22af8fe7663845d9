// Multi-level partition of unity implicits (Ohtake, Belyaev, Alexa, Turk and
// Seidel, SIGGRAPH 2003) from oriented points: an octree over the points
// whose cells each fit a local function to the points in a ball around them,
// refined where the fit misses by more than the accuracy asked for, and
// blended by compactly supported weights:
//
//   f(x) = sum_i w_i(x) Q_i(x) / sum_i w_i(x),  w_i(x) = (1 - |x - c_i|^2 / R_i^2)^3.
//
// Local functions are the paper's three kinds: a quadratic height function
// over the points' mean plane where the normals agree; a general quadric
// (fitted to the points and to auxiliary points along their normals) where
// they do not: thin parts, both sides of a sheet, folds; and, where neither
// meets the accuracy and the normals fall into two or three clusters, an
// edge or corner function: the max or min of one height function per
// cluster (max where the edge is convex, min where it is concave), so sharp
// edges stay sharp instead of rounding at the accuracy. Negative inside.
//
// Bounds for sphere tracing are proven, not sampled: over a box, f is a
// convex combination of the Q_i whose supports reach it, so its range lies
// in the hull of their interval ranges; its gradient
//   grad f = sum_i [w_i grad Q_i + (Q_i - f) grad w_i] / W
// is bounded by the largest |grad Q_i| plus the range's width times
// sum_i |grad w_i|max / W_min, where W_min > 0 because every point of the
// domain lies in an octree cell whose own ball reaches at least
// 1 / (2 support) of its radius beyond it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "geometry/bounding_box.h"
#include "geometry/interval.h"
#include "geometry/variational/variational_field.h"
#include "geometry/vector_types.h"

namespace isotrace::geometry {

struct MpuSumRows;

template <int Degree>
class SegmentPolynomialSum;

struct MpuPoint {
    Vec3 position;
    Vec3 normal;  ///< outward, unit
};

struct MpuOptions {
    /// Largest distance of the points to the surface of their local fit,
    /// relative to the points' bounding diagonal.
    double accuracy = 2e-3;
    /// Ball radius over cell diagonal (the paper's alpha); above 0.5.
    double support = 0.75;
    int maxDepth = 10;
    /// Points a ball must hold; smaller balls grow until they do.
    int minPoints = 15;
    /// Edge and corner functions where smooth ones miss the accuracy.
    bool sharpFeatures = true;
};

/// Q(x) = c0 + g . y + y^T A y in y = x - origin.
struct MpuQuadric {
    Vec3 origin = Vec3::Zero();
    Mat3 A = Mat3::Zero();
    Vec3 g = Vec3::Zero();
    double c0 = 0;

    /// Inline: a blend's sums and every model fit evaluate dozens per point.
    double evaluate(const Vec3& x, Vec3* gradient) const {
        const Vec3 y = x - origin;
        const Vec3 Ay = A * y;
        if (gradient) *gradient = g + 2.0 * Ay;
        return c0 + g.dot(y) + y.dot(Ay);
    }
    Interval range(const Box3& box) const;
    double gradientBound(const Box3& box) const;
};

/// How a local function combines its quadrics (pieces p0, p1, p2).
enum class MpuCombination : uint8_t {
    Single,    ///< p0
    Max,       ///< max of all: a convex edge or corner
    Min,       ///< min of all: a concave edge or corner
    MaxOfMin,  ///< max(min(p0, p1), p2): a corner with one concave edge (p0, p1)
    MinOfMax,  ///< min(max(p0, p1), p2): a corner with one convex edge (p0, p1)
    /// An r^3 interpolant, interpolants()[first], instead of pieces: the
    /// locals of a partition-of-unity variational fit
    /// (pointsets/variational_partition.h).
    Interpolant,
};

/// One local function: its ball and its pieces, pieces[first, first + count)
/// (or its interpolant).
struct MpuLocal {
    Vec3 center = Vec3::Zero();
    double radius = 0;
    uint32_t first = 0;
    uint8_t count = 1;
    MpuCombination combination = MpuCombination::Single;
};

/// The one rule of how a local's pieces combine, for values, values with
/// gradients and interval ranges alike: v holds the pieces' values (or
/// ranges), larger and smaller pick between two of them.
template <class T, class Larger, class Smaller>
T combineMpuPieces(const MpuLocal& l, const T* v, Larger larger, Smaller smaller) {
    switch (l.combination) {
    case MpuCombination::Single:
    case MpuCombination::Interpolant: break;  // no pieces to combine
    case MpuCombination::Max: return l.count == 3 ? larger(larger(v[0], v[1]), v[2]) : larger(v[0], v[1]);
    case MpuCombination::Min: return l.count == 3 ? smaller(smaller(v[0], v[1]), v[2]) : smaller(v[0], v[1]);
    case MpuCombination::MaxOfMin: return larger(smaller(v[0], v[1]), v[2]);
    case MpuCombination::MinOfMax: return smaller(larger(v[0], v[1]), v[2]);
    }
    return v[0];
}

/// The value (and gradient, where asked) of a local made of quadric pieces
/// (any combination but Interpolant), its pieces at `pieces`.
double evaluateMpuPieces(const MpuLocal& l, const MpuQuadric* pieces, const Vec3& x, Vec3* gradient);

/// A list of locals (indices into MpuField::locals()) whose first `singles`
/// are single-piece locals, which sums over the list take together.
/// The sharp locals after them may be known to take one piece wherever the
/// list is asked about (a tracer's part proves it over its box): the first
/// kResolvedSharp of them carry 2 bits each in `sharpPieces`, 0 where the
/// local may take any of its pieces, k + 1 where it takes piece k.
struct MpuLocalList {
    static constexpr size_t kResolvedSharp = 16;

    std::span<const uint32_t> indices;
    size_t singles = 0;
    uint32_t sharpPieces = 0;

    MpuLocalList(std::span<const uint32_t> all, size_t singleCount = 0, uint32_t sharpPieceCodes = 0)
        : indices(all), singles(singleCount), sharpPieces(sharpPieceCodes) {}
    std::span<const uint32_t> singleLocals() const { return indices.first(singles); }
    /// The rest, summed one by one.
    std::span<const uint32_t> otherLocals() const { return indices.subspan(singles); }
    /// The piece the k-th of otherLocals() takes, or -1 where not known.
    int pieceOf(size_t k) const { return k < kResolvedSharp ? int((sharpPieces >> (2 * k)) & 3u) - 1 : -1; }
    /// The code of sharpPieces for the k-th of otherLocals() taking `piece`.
    static uint32_t pieceCode(size_t k, int piece) {
        return k < kResolvedSharp && piece >= 0 ? uint32_t(piece + 1) << (2 * k) : 0u;
    }
};

/// The blend's sums at a point: f = N / W, with N = sum_i w_i Q_i and
/// W = sum_i w_i (plus the background's term), and their gradients.
struct MpuBlendSums {
    double N = 0.0, W = 0.0;
    Vec3 gradientN = Vec3::Zero(), gradientW = Vec3::Zero();
    double value() const { return N / W; }
    Vec3 gradient() const { return (gradientN * W - N * gradientW) / (W * W); }
};

struct MpuReport {
    size_t localFunctions = 0;
    size_t generalQuadrics = 0;  ///< cells where normals disagree
    size_t edges = 0, corners = 0;  ///< sharp-feature functions of two and three pieces
    int depth = 0;
    double maxError = 0.0;   ///< of the blended field at the input points, relative to their diagonal
    double meanError = 0.0;  ///< the mean of the same
    double seconds = 0.0;
};

class MpuField {
public:
    /// Throws std::invalid_argument for fewer than minPoints points,
    /// non-finite values or bad options.
    static MpuField fit(const std::vector<MpuPoint>& points, const MpuOptions& options = {}, MpuReport* report = nullptr);
    /// A field from its parts, as a saved fit gives them back; throws
    /// std::invalid_argument when they do not make a field (pieces out of
    /// range, non-finite numbers, an empty domain).
    static MpuField fromParts(const Box3& domain, double support, double backgroundMargin, std::vector<MpuLocal> locals,
                              std::vector<MpuQuadric> pieces, std::vector<VariationalField> interpolants = {});

    double value(const Vec3& p) const;
    double valueAndGradient(const Vec3& p, Vec3& gradient) const;
    /// The same from a list of locals (indices into locals()) that holds
    /// every one whose ball reaches p, as a tracing part keeps them.
    double valueAndGradient(const Vec3& p, Vec3& gradient, std::span<const uint32_t> locals) const;
    /// N and W and their gradients from such a list (tracers that root-find
    /// on N, which has f's zeros and is smooth where f's quotient is not).
    MpuBlendSums blendSums(const Vec3& p, MpuLocalList locals) const;
    /// N alone (its sign is f's).
    double numerator(const Vec3& p, MpuLocalList locals) const;
    /// Adds to `sum` the single-piece locals' terms w_i Q_i along the
    /// segment p0 + u D, u in [0, 1], as polynomials of degree 8 on the span
    /// of u inside each ball; returns how many balls the
    /// segment meets (pointsets/mpu_ray_segment.h sums the rest).
    int addSinglesAlongSegment(const Vec3& p0, const Vec3& D, std::span<const uint32_t> singles,
                               SegmentPolynomialSum<8>& sum) const;
    /// Indices of the locals whose ball reaches the box.
    void localsTouching(const Box3& box, std::vector<uint32_t>& out) const;
    /// The list in the order MpuLocalList asks for: its single-piece locals
    /// moved to the front (order among each kind kept).
    MpuLocalList singlesFirst(std::span<uint32_t> list) const;
    /// The value, and a radius around p proven free of zeros: from the
    /// Lipschitz bound over a small box around p, far tighter than a
    /// tracing cell's (the weights' slopes there multiply only the local
    /// functions' disagreement, not their spread over the whole cell).
    double valueAndSafeDistance(const Vec3& p, double& safeDistance) const;
    Interval range(const Box3& box) const;
    double lipschitz(const Box3& box) const;
    Box3 bounds() const { return domain_; }
    /// How far blendSums and numerator over lists with single-piece locals
    /// may stray from the same sums taken one by one, relative to the
    /// magnitudes summed (1 + |N| + |grad N| + W): both sum in doubles, in
    /// another order.
    static constexpr double kSumRelativeError = 1e-12;
    /// Terms summed at a typical point (evaluation cost): local functions,
    /// or for interpolants their centres.
    size_t termCount() const { return typicalTerms_; }

    /// A faint background term keeps f defined beyond the balls: weight
    /// kBackgroundWeight, value the distance to the domain plus the
    /// background margin (so just the margin inside the domain).
    static constexpr double kBackgroundWeight = 1e-6;

    // The parts, for saving (and for tracers that work on them).
    const std::vector<MpuLocal>& locals() const { return locals_; }
    const std::vector<MpuQuadric>& pieces() const { return pieces_; }
    const std::vector<VariationalField>& interpolants() const { return interpolants_; }
    /// |A| of pieces()[i] (Frobenius, rounded up): at least |u^T A u| for unit u.
    double pieceCurvature(size_t i) const { return pieceCurvatures_[i]; }
    /// Some local is an interpolant (tracers built for quadrics decline).
    bool hasInterpolants() const { return !interpolants_.empty(); }
    double support() const { return support_; }
    /// Never the same for two fields built (copies share it, and their
    /// values): a key for caches of values that outlive a field.
    uint64_t id() const { return id_; }
    double backgroundMargin() const { return backgroundMargin_; }

private:
    using Local = MpuLocal;
    double evaluate(const Local& l, const Vec3& x, Vec3* gradient) const;
    Interval range(const Local& l, const Box3& box) const;
    double gradientBound(const Local& l, const Box3& box) const;
    /// Indexes the locals and sets the weights' lower bound.
    void finish();
    /// The grid cell along `axis` holding a coordinate, clamped to the grid.
    int gridIndex(double coordinate, int axis) const;

    template <class Visit>
    void forLocalsAt(const Vec3& p, Visit&& visit) const;
    /// visit(local, distance range from its centre to the box) for every
    /// local whose ball reaches the box, once each.
    template <class Visit>
    void forLocalsTouching(const Box3& box, Visit&& visit) const;

    /// forLocals(visit) calls visit(local, piece) for each local to sum:
    /// piece -1 where the local's combination decides, else the one it takes.
    template <class ForLocals>
    MpuBlendSums sums(const Vec3& p, ForLocals&& forLocals) const;
    /// A local's function, or its piece `piece` where that is known (>= 0).
    double evaluate(const Local& l, int piece, const Vec3& x, Vec3* gradient) const {
        return piece >= 0 ? pieces_[l.first + piece].evaluate(x, gradient) : evaluate(l, x, gradient);
    }
    /// The share of the sums of the listed rows of one-piece terms
    /// (single-piece locals, and pieces sharp locals are resolved to).
    void addOnePieceSums(const Vec3& p, std::span<const uint32_t> rows, MpuBlendSums& s) const;
    double onePieceNumerator(const Vec3& p, std::span<const uint32_t> rows) const;
    template <class ForLocals>
    double blend(const Vec3& p, Vec3& gradient, ForLocals&& forLocals) const;
    double background(const Vec3& p, Vec3* gradient) const;

    std::vector<Local> locals_;
    std::vector<MpuQuadric> pieces_;
    std::vector<VariationalField> interpolants_;
    Box3 domain_;
    double support_ = 0.75;
    // A uniform grid over the domain: each cell lists the locals whose ball reaches it.
    int grid_ = 1;
    Vec3 cellSize_ = Vec3::Ones();
    std::vector<uint32_t> cellStart_, cellItems_;
    // The same lists for balls within nearMargin_ of each cell.
    double nearMargin_ = 0.0;
    std::vector<uint32_t> nearStart_, nearItems_;
    std::vector<double> pieceCurvatures_;  ///< |A| of each piece
    /// The one-piece terms in the layout the vectorized sums read (a type
    /// private to the library); built once, shared by copies.
    std::shared_ptr<const MpuSumRows> sumRows_;
    /// Splits `locals` for the vectorized sums: calls onRows(rows) once with
    /// the rows of one-piece terms (the single-piece locals', and the pieces
    /// the sharp locals are resolved to where the list is short enough) and
    /// visitRest(local, piece) for each local summed one by one.
    template <class OnRows, class VisitRest>
    void forRowsOf(MpuLocalList locals, OnRows&& onRows, VisitRest&& visitRest) const;
    double minimumWeight_ = 0.0;
    double backgroundMargin_ = 0.0;
    size_t typicalTerms_ = 1;
    uint64_t id_ = 0;
};

/// MPU's weight (1 - r^2 / R^2)^3 at squared distance r2 from the centre of
/// a ball of squared radius R2; 0 beyond.
inline double mpuWeight(double r2, double radius2) {
    if (r2 >= radius2) return 0.0;
    const double s = 1.0 - r2 / radius2;
    return s * s * s;
}

/// The largest |grad w| over distances in `distance` from the centre of a
/// ball of radius R.
double mpuWeightSlope(const Interval& distance, double R);

}  // namespace isotrace::geometry
