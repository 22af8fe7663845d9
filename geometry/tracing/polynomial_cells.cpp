#include "geometry/tracing/polynomial_cells.h"

#include <algorithm>
#include <vector>

#include "geometry/bernstein_root.h"
#include "geometry/content_hash.h"
#include "geometry/fields/polynomial.h"

namespace isotrace::geometry {

namespace {

// A polynomial split for restriction to lines: the constant, the terms in
// one variable as dense coefficients per axis (Goursat's tangle and its kin
// have no others), and the terms mixing variables.
template <int Degree>
struct SplitPolynomial {
    double constant = 0.0;
    std::array<Monomials<Degree>, 3> univariate{};  ///< coefficient of x_a^k at [a][k], k >= 1
    std::array<int, 3> univariateDegree{0, 0, 0};
    /// Terms mixing variables, sorted by their powers (x's, then y's, then
    /// z's): alongLine sums them by nested Horner steps.
    std::vector<PolynomialTerm> mixed;
    int mixedMaxZPower = 0;

    explicit SplitPolynomial(const Polynomial& p) {
        for (const PolynomialTerm& t : p.terms()) {
            const int variables = (t.powers[0] > 0) + (t.powers[1] > 0) + (t.powers[2] > 0);
            if (variables == 0) {
                constant += t.coefficient;
            } else if (variables == 1) {
                const int axis = t.powers[0] > 0 ? 0 : t.powers[1] > 0 ? 1 : 2;
                univariate[axis][t.powers[axis]] += t.coefficient;
                univariateDegree[axis] = std::max(univariateDegree[axis], t.powers[axis]);
            } else {
                mixed.push_back(t);
                mixedMaxZPower = std::max(mixedMaxZPower, t.powers[2]);
            }
        }
        std::sort(mixed.begin(), mixed.end(),
                  [](const PolynomialTerm& a, const PolynomialTerm& b) { return a.powers < b.powers; });
    }

    /// The polynomial along x(s) = x0 + s D, in monomials of s (the degree
    /// bounds every product, so nothing is truncated).
    Monomials<Degree> alongLine(const Vec3& x0, const Vec3& D) const {
        Monomials<Degree> sum{};
        sum[0] = constant;
        // One-variable terms: g(x0 + sD) = sum_j g^(j)(x0) / j! (sD)^j, the
        // Taylor coefficients at x0 by repeated synthetic division.
        for (int axis = 0; axis < 3; ++axis) {
            const int n = univariateDegree[axis];
            if (n == 0) continue;
            Monomials<Degree> c = univariate[axis];
            const double x = x0[axis];
            for (int i = 0; i < n; ++i)
                for (int k = n - 1; k >= i; --k) c[k] += x * c[k + 1];
            double power = 1.0;
            for (int j = 0; j <= n; ++j, power *= D[axis]) sum[j] += c[j] * power;
        }
        if (mixed.empty()) return sum;
        // Mixed terms: z's powers along the line, z(s)^k.
        std::array<Monomials<Degree>, Degree + 1> zPowers;
        zPowers[0] = {};
        zPowers[0][0] = 1.0;
        for (int k = 1; k <= mixedMaxZPower; ++k) {
            zPowers[k] = {};
            for (int i = 0; i < k; ++i) {
                zPowers[k][i] += zPowers[k - 1][i] * x0[2];
                zPowers[k][i + 1] += zPowers[k - 1][i] * D[2];
            }
        }
        // Nested Horner over the sorted terms: in x, each x^a's part (in y,
        // each y^b's part: its z terms, a sum of z's powers) multiplied by the
        // linear x(s) once per power, so a term costs O(degree), not the two
        // products of polynomials it cost alone (the decocube has 65 such
        // terms: 80% of its frame was spent here).
        // p *= (x0 + s D) along `axis`; degree tracked, so the top term is new.
        auto timesLinear = [&](Monomials<Degree>& p, int& degree, int axis) {
            if (degree < 0) return;
            p[degree + 1] = D[axis] * p[degree];
            for (int k = degree; k > 0; --k) p[k] = x0[axis] * p[k] + D[axis] * p[k - 1];
            p[0] *= x0[axis];
            ++degree;
        };
        // Terms [from, to), which share their powers of the axes before
        // `axis` and are sorted by this one's, along the line, into `out`
        // (zero on entry); returns the degree reached (-1: none).
        auto part = [&](auto&& self, int axis, size_t from, size_t to, Monomials<Degree>& out) -> int {
            int degree = -1;
            if (axis == 2) {
                for (size_t t = from; t < to; ++t) {
                    const int c = mixed[t].powers[2];
                    for (int k = 0; k <= c; ++k) out[k] += mixed[t].coefficient * zPowers[c][k];
                    degree = std::max(degree, c);
                }
                return degree;
            }
            size_t end = to;
            for (int power = mixed[to - 1].powers[axis]; power >= 0; --power) {
                timesLinear(out, degree, axis);
                size_t begin = end;
                while (begin > from && mixed[begin - 1].powers[axis] == power) --begin;
                if (begin < end) {
                    Monomials<Degree> inner{};
                    const int innerDegree = self(self, axis + 1, begin, end, inner);
                    for (int k = 0; k <= innerDegree; ++k) out[k] += inner[k];
                    degree = std::max(degree, innerDegree);
                }
                end = begin;
            }
            return degree;
        };
        Monomials<Degree> mixedSum{};
        const int degree = part(part, 0, 0, mixed.size(), mixedSum);
        for (int k = 0; k <= degree; ++k) sum[k] += mixedSum[k];
        return sum;
    }
};

// The polynomial along the ray a thread traced last: a ray crosses many
// parts of the same surface, and each needs only its own interval of it.
template <int Degree>
struct RayPolynomial {
    uint64_t surface = 0;  ///< content key of the polynomial and its placement
    Vec3 origin = Vec3::Zero(), direction = Vec3::Zero();
    double expandedAt = 0.0;  ///< t of the expansion point (near the surface, for conditioning)
    Monomials<Degree> p{};    ///< in s = t - expandedAt
};

// What every cell of one surface shares (built once, not per cell: copies
// of the polynomial were most of the tangle's start-up).
template <int Degree>
struct PolynomialSurface {
    PolynomialField field;
    SplitPolynomial<Degree> split;
    LeafPlacement placement;
    uint64_t key;  ///< content key (surfaceKey)
    Vec3 centre;   ///< of the domain, where rays' polynomials are expanded

    PolynomialSurface(const PolynomialField& f, const LeafPlacement& p, uint64_t k)
        : field(f), split(f.polynomial()), placement(p), key(k), centre(f.domain.center()) {}
};

template <int Degree>
class PolynomialCellTracer final : public CellTracer {
public:
    PolynomialCellTracer(std::shared_ptr<const PolynomialSurface<Degree>> surface, bool negated, const Box3& part)
        : surface_(std::move(surface)), sign_(negated ? -1.0 : 1.0), part_(part) {}

    CellTraceResult trace(uint32_t, const PartBand&, const PartPayload&, const Vec3& origin, const Vec3& direction,
                          double t0, double t1, const TraceSettings& settings) const override {
        const PolynomialSurface<Degree>& surface = *surface_;
        Vec3 o, d;
        rayInLeafFrame(surface.placement, origin, direction, o, d);
        if (!surface.placement.identity && !clipRayToBox(part_, o, d, t0, t1)) return {};
        CellTraceResult r;
        if (!(t1 > t0)) return r;
        thread_local RayPolynomial<Degree> ray;
        if (ray.surface != surface.key || ray.origin != o || ray.direction != d) {
            ray.surface = surface.key;
            ray.origin = o;
            ray.direction = d;
            // Expanded where the ray passes closest to the domain's centre:
            // monomials in t about a far origin would cancel badly.
            ray.expandedAt = (surface.centre - o).dot(d) / d.squaredNorm();
            ray.p = surface.split.alongLine(o + ray.expandedAt * d, d);
        }
        BernsteinRootStats stats;
        const auto s = firstBernsteinRoot<Degree>(ray.p, t0 - ray.expandedAt, t1 - ray.expandedAt,
                                                  settings.epsilon / direction.norm(), &stats, settings.anyHit);
        r.steps = 1 + stats.subdivisions;
        r.evaluations = uint64_t(r.steps + stats.evaluations);
        if (!s) return r;
        recordHit(r, ray.expandedAt + *s, surface.field, o, d, surface.placement, sign_);
        return r;
    }

private:
    std::shared_ptr<const PolynomialSurface<Degree>> surface_;
    double sign_;  ///< -1 for the complement (a carving operand)
    Box3 part_;  ///< in the leaf's frame
};

// Every cell of one surface gets the same key, whatever program copy it
// holds: the terms, the domain and the placement, hashed.
uint64_t surfaceKey(const PolynomialField& field, const LeafPlacement& placement) {
    auto bytes = [](const auto& value) { return std::string_view(reinterpret_cast<const char*>(&value), sizeof value); };
    uint64_t h = kFnvOffsetBasis;
    for (const PolynomialTerm& t : field.polynomial().terms()) h = fnv1a64(bytes(t.powers), fnv1a64(bytes(t.coefficient), h));
    h = fnv1a64(bytes(field.domain.lower), fnv1a64(bytes(field.domain.upper), h));
    h = fnv1a64(bytes(placement.linear), fnv1a64(bytes(placement.offset), fnv1a64(bytes(placement.valueScale), h)));
    return h | 1;  // never 0, the empty cache's key
}

}  // namespace

template <int Degree>
std::unique_ptr<CellTracer> PolynomialCellAccelerator::tracerFor(const PolynomialField& field,
                                                                const LeafPlacement& placement, uint64_t key,
                                                                bool negated, const Box3& part) const {
    std::shared_ptr<const void>* shared;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        shared = &surfaces_[key];
        if (!*shared) *shared = std::make_shared<const PolynomialSurface<Degree>>(field, placement, key);
    }
    return std::make_unique<PolynomialCellTracer<Degree>>(
        std::static_pointer_cast<const PolynomialSurface<Degree>>(*shared), negated, part);
}

bool PolynomialCellAccelerator::marchesWholeField(const FieldProgram& field, const Box3&) const {
    const PolynomialField* polynomial = bareShape<PolynomialField>(field);
    const int degree = polynomial ? polynomial->polynomial().degree() : 0;
    return degree >= 1 && degree <= kMaxDegree;
}

std::optional<CellAcceleration> PolynomialCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                                      double) const {
    const ShapeCell<PolynomialField> cell(program, box);
    if (!cell.shape) return std::nullopt;
    const int degree = cell.shape->polynomial().degree();
    if (degree < 1 || degree > kMaxDegree) return std::nullopt;
    // One part per cell, the cell shrunk to the surface: splitting it
    // further made rays cross more parts, each a call from Embree.
    CellAcceleration a;
    if (cell.part.isEmpty()) return a;
    a.parts = worldPartBoxes(*cell.placement, {cell.part}, box);
    const PolynomialField& field = *cell.shape;
    const LeafPlacement& placement = *cell.placement;
    const uint64_t key = surfaceKey(field, placement);
    if (degree <= 2) a.tracer = tracerFor<2>(field, placement, key, cell.negated, cell.part);
    else if (degree <= 4) a.tracer = tracerFor<4>(field, placement, key, cell.negated, cell.part);
    else if (degree <= 6) a.tracer = tracerFor<6>(field, placement, key, cell.negated, cell.part);
    else if (degree <= 8) a.tracer = tracerFor<8>(field, placement, key, cell.negated, cell.part);
    else if (degree <= 12) a.tracer = tracerFor<12>(field, placement, key, cell.negated, cell.part);
    else a.tracer = tracerFor<16>(field, placement, key, cell.negated, cell.part);
    return a;
}

}  // namespace isotrace::geometry
