#include "geometry/tracing/blob_cells.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry/segment_polynomial.h"

namespace isotrace::geometry {

namespace {

// The kernel as a cubic in q = a^2.
Monomials<3> kernelInSquaredRadius(BlobKernel kernel) {
    if (kernel == BlobKernel::Poly6) return {1.0, -3.0, 3.0, -1.0};  // (1 - q)^3
    return {1.0, -22.0 / 9.0, 17.0 / 9.0, -4.0 / 9.0};             // Wyvill's soft object
}

// Adds -w k(r / R) of a shaped blob along the segment p0 + u D, u in [0, 1].
// In the blob's frame the point moves on a line, and each axis's offset
// from the core is linear in u between the points where the line crosses
// the core's faces, so r^2 is a quadratic in u on each piece (at most 7)
// and the term one polynomial of degree 6 where r < R.
bool addShapedTerm(SegmentPolynomialSum<6>& sum, const Monomials<3>& kernel, const Blob& b, const BlobShape& shape,
                   const Vec3& p0, const Vec3& D) {
    const Vec3 q0 = shape.toLocal * (p0 - b.center), dq = shape.toLocal * D;
    const Vec3& h = shape.halfSize;
    double cuts[8];
    int n = 0;
    cuts[n++] = 0.0;
    for (int axis = 0; axis < 3; ++axis) {
        if (!(h[axis] > 0.0) || dq[axis] == 0.0) continue;
        for (const double face : {-h[axis], h[axis]}) {
            const double u = (face - q0[axis]) / dq[axis];
            if (u > 0.0 && u < 1.0) cuts[n++] = u;
        }
    }
    cuts[n++] = 1.0;
    std::sort(cuts, cuts + n);
    const double R2 = b.radius * b.radius;
    bool reached = false;
    for (int k = 0; k + 1 < n; ++k) {
        const double from = cuts[k], to = cuts[k + 1];
        if (!(to > from)) continue;
        // r^2 = c0 + c1 u + c2 u^2 on this piece: the axes outside the core
        // in its middle contribute (q - face)^2.
        const double middle = 0.5 * (from + to);
        double c0 = 0.0, c1 = 0.0, c2 = 0.0;
        for (int axis = 0; axis < 3; ++axis) {
            const double q = q0[axis] + middle * dq[axis];
            if (q >= -h[axis] && q <= h[axis]) continue;
            const double g0 = q0[axis] - (q > 0.0 ? h[axis] : -h[axis]);
            c0 += g0 * g0;
            c1 += 2.0 * g0 * dq[axis];
            c2 += dq[axis] * dq[axis];
        }
        double enter = from, leave = to;
        if (c2 > 0.0) {
            const double disc = c1 * c1 - 4.0 * c2 * (c0 - R2);
            if (!(disc > 0.0)) continue;
            const double root = std::sqrt(disc);
            enter = std::max(from, (-c1 - root) / (2.0 * c2));
            leave = std::min(to, (-c1 + root) / (2.0 * c2));
        } else if (!(c0 < R2)) {
            continue;
        }
        if (!(leave > enter)) continue;
        Monomials<6> term = composeWithQuadratic<3>(kernel, c0 / R2, c1 / R2, c2 / R2);
        for (double& c : term) c *= -b.weight;
        sum.add(term, enter, leave);
        reached = true;
    }
    return reached;
}

// One part: an octant of the cell that may hold surface, with the blobs
// that reach it (contiguous, read in order by every ray through it).
struct BlobPart {
    Box3 box;  ///< in the leaf's frame
    uint32_t first = 0, count = 0;
};

class BlobCellTracer final : public CellTracer {
public:
    BlobCellTracer(const BlobbyField& field, const LeafPlacement& placement, std::vector<BlobPart> parts,
                   std::vector<Blob> blobs)
        : kernel_(kernelInSquaredRadius(field.kernel)),
          threshold_(field.threshold),
          field_(field),
          placement_(placement),
          parts_(std::move(parts)),
          blobs_(std::move(blobs)) {}

    CellTraceResult trace(uint32_t index, const PartBand&, const PartPayload&, const Vec3& origin,
                          const Vec3& direction, double t0, double t1, const TraceSettings& settings) const override {
        const BlobPart& part = parts_[index];
        Vec3 o, d;
        rayInLeafFrame(placement_, origin, direction, o, d);
        if (!placement_.identity && !clipRayToBox(part.box, o, d, t0, t1)) return {};
        CellTraceResult r;
        if (!(t1 > t0)) return r;
        thread_local SegmentPolynomialSum<6> sum;  // grows once per thread, then reused
        sum.clear();
        sum.addConstant(threshold_);
        const Vec3 p0 = o + t0 * d, D = (t1 - t0) * d;
        const double DD = D.squaredNorm();
        for (uint32_t i = part.first; i < part.first + part.count; ++i) {
            const Blob& b = blobs_[i];
            if (b.shape != kRoundBlob) {
                r.evaluations += addShapedTerm(sum, kernel_, b, (*field_.shapes)[b.shape], p0, D);
                continue;
            }
            // a^2 along the segment: (|r0|^2 + 2 u r0.D + u^2 DD) / R^2.
            const Vec3 r0 = p0 - b.center;
            const double R2 = b.radius * b.radius, r0D = r0.dot(D);
            const double disc = r0D * r0D + DD * (R2 - r0.squaredNorm());
            if (!(disc > 0.0)) continue;
            const double root = std::sqrt(disc), enter = (-r0D - root) / DD, leave = (-r0D + root) / DD;
            if (!(leave > 0.0 && enter < 1.0)) continue;
            ++r.evaluations;
            Monomials<6> term = composeWithQuadratic<3>(kernel_, r0.squaredNorm() / R2, 2.0 * r0D / R2, DD / R2);
            for (double& c : term) c *= -b.weight;
            sum.add(term, enter, leave);
        }
        const auto found = sum.firstRoot(settings.epsilon / direction.norm() / (t1 - t0));
        r.steps = found.pieces;
        if (!found.found) return r;
        r.hit = true;
        r.t = t0 + found.u * (t1 - t0);
        // The gradient from the part's blobs (all that reach the hit).
        const Vec3 p = o + r.t * d;
        Vec3 gradient = Vec3::Zero();
        for (uint32_t i = part.first; i < part.first + part.count; ++i) gradient -= field_.termGradient(blobs_[i], p);
        r.gradientKnown = true;
        r.gradient = worldGradient(placement_, gradient);
        return r;
    }

private:
    Monomials<3> kernel_;
    double threshold_;
    BlobbyField field_;  ///< the kernel's settings and shapes (its blobs live in the parts)
    LeafPlacement placement_;
    std::vector<BlobPart> parts_;
    std::vector<Blob> blobs_;
};

}  // namespace

std::optional<CellAcceleration> BlobCellAccelerator::accelerate(const FieldProgram& program, const Box3& box,
                                                                double) const {
    const FieldLeaf* leaf = program.singleLeaf();
    const auto* blobby = leaf ? std::get_if<BlobbyField>(&leaf->shape) : nullptr;
    if (!blobby || (blobby->kernel != BlobKernel::Poly6 && blobby->kernel != BlobKernel::SoftObject))
        return std::nullopt;
    const LeafPlacement& placement = leaf->placement;
    const Box3 leafBox = placement.leafFromWorld(box);
    // One halving: octants the interval range proves empty drop out, and a
    // ray through an octant pays only for the blobs that reach it.
    std::vector<BlobPart> parts;
    std::vector<Blob> blobs;
    for (int k = 0; k < 8; ++k) {
        const Box3 octant = leafBox.octant(k);
        const BlobbyField near = blobby->prunedTo(octant);
        if (!near.range(octant).containsZero()) continue;
        parts.push_back({octant, uint32_t(blobs.size()), uint32_t(near.blobs.size())});
        blobs.insert(blobs.end(), near.blobs.begin(), near.blobs.end());
    }
    CellAcceleration a;
    std::vector<Box3> boxes;
    for (const BlobPart& part : parts) boxes.push_back(part.box);
    a.parts = worldPartBoxes(placement, boxes, box);
    BlobbyField settings = *blobby;
    settings.blobs.clear();
    a.tracer = std::make_unique<BlobCellTracer>(settings, placement, std::move(parts), std::move(blobs));
    return a;
}

}  // namespace isotrace::geometry
