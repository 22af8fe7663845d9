#include "geometry/tracing/shape_spans.h"

#include <algorithm>
#include <cmath>

#include "geometry/quadratic_roots.h"
#include "geometry/tracing/sphere_tracer.h"

namespace isotrace::geometry {

bool sphereSpan(const SphereField& sphere, const Vec3& o, const Vec3& d, double& enter, double& leave) {
    // |o - c + t d|^2 = r^2: a t^2 + 2 b t + c = 0.
    const Vec3 oc = o - sphere.center;
    return quadraticRoots(d.squaredNorm(), oc.dot(d), oc.squaredNorm() - sphere.radius * sphere.radius, enter, leave);
}

RoundedBoxPieces::RoundedBoxPieces(const BoxField& box, const Box3& region)
    : centre_(box.center), rounding_(box.rounding) {
    const Box3 local(region.lower - centre_, region.upper - centre_);
    auto keep = [&](const Piece& piece) {
        if (!intersection(piece.extent, local).isEmpty()) pieces_.push_back(piece);
    };
    const double r = box.rounding;
    const Vec3 core = (box.halfSize - Vec3::Constant(r)).cwiseMax(0.0);
    if (!(r > 0)) {
        keep({Piece::Kind::Slab, 0, Vec3::Zero(), {-core, core}});
        return;
    }
    for (int axis = 0; axis < 3; ++axis) {
        Vec3 half = core;
        half[axis] += r;
        keep({Piece::Kind::Slab, axis, Vec3::Zero(), {-half, half}});
    }
    for (int axis = 0; axis < 3; ++axis) {
        const int i = (axis + 1) % 3, j = (axis + 2) % 3;
        for (double si : {-1.0, 1.0})
            for (double sj : {-1.0, 1.0}) {
                Vec3 c = Vec3::Zero();
                c[i] = si * core[i];
                c[j] = sj * core[j];
                Vec3 lo = c - Vec3::Constant(r), hi = c + Vec3::Constant(r);
                lo[axis] = -core[axis];
                hi[axis] = core[axis];
                keep({Piece::Kind::Cylinder, axis, c, {lo, hi}});
            }
    }
    for (double sx : {-1.0, 1.0})
        for (double sy : {-1.0, 1.0})
            for (double sz : {-1.0, 1.0}) {
                const Vec3 c(sx * core.x(), sy * core.y(), sz * core.z());
                keep({Piece::Kind::Ball, 0, c, {c - Vec3::Constant(r), c + Vec3::Constant(r)}});
            }
}

bool RoundedBoxPieces::pieceSpan(const Piece& piece, const Vec3& o, const Vec3& d, double t0, double t1,
                                 double& enter, double& leave) const {
    const double r = rounding_;
    enter = t0, leave = t1;
    switch (piece.kind) {
        case Piece::Kind::Slab:
            return clipRayToBox(piece.extent, o, d, enter, leave);
        case Piece::Kind::Cylinder: {
            const int i = (piece.axis + 1) % 3, j = (piece.axis + 2) % 3;
            const double oi = o[i] - piece.centre[i], oj = o[j] - piece.centre[j];
            const double a = d[i] * d[i] + d[j] * d[j], b = oi * d[i] + oj * d[j], c = oi * oi + oj * oj - r * r;
            if (a > 0) {
                double near, far;
                if (!quadraticRoots(a, b, c, near, far)) return false;
                enter = std::max(enter, near), leave = std::min(leave, far);
            } else if (!(c <= 0)) {
                return false;  // parallel to the axis, outside the tube
            }
            // Along its axis the cylinder ends with the edge.
            Box3 along(Vec3::Constant(-INFINITY), Vec3::Constant(INFINITY));
            along.lower[piece.axis] = piece.extent.lower[piece.axis];
            along.upper[piece.axis] = piece.extent.upper[piece.axis];
            return clipRayToBox(along, o, d, enter, leave);
        }
        case Piece::Kind::Ball: {
            const Vec3 oc = o - piece.centre;
            double near, far;
            if (!quadraticRoots(d.squaredNorm(), oc.dot(d), oc.squaredNorm() - r * r, near, far)) return false;
            enter = std::max(enter, near), leave = std::min(leave, far);
            return enter <= leave;
        }
    }
    return false;
}

bool RoundedBoxPieces::span(const Vec3& o, const Vec3& d, double t0, double t1, double& enter, double& leave) const {
    const Vec3 local = o - centre_;
    enter = INFINITY, leave = -INFINITY;
    for (const Piece& piece : pieces_) {
        double e, l;
        if (!pieceSpan(piece, local, d, t0, t1, e, l)) continue;
        enter = std::min(enter, e), leave = std::max(leave, l);
    }
    return enter <= leave;
}

Monomials<4> torusQuarticAlongRay(const TorusField& torus, const Vec3& o, const Vec3& D, double& tc) {
    // g = |d|^2 + R^2 - r^2 and h = d_x^2 + d_z^2 are quadratics in s; the
    // quartic is g^2 - 4 R^2 h.
    tc = (torus.center - o).dot(D) / D.squaredNorm();
    const Vec3 d0 = o + tc * D - torus.center;
    const double R2 = torus.major * torus.major;
    const double g0 = d0.squaredNorm() + R2 - torus.minor * torus.minor, g1 = 2.0 * d0.dot(D), g2 = D.squaredNorm();
    const double h0 = d0.x() * d0.x() + d0.z() * d0.z(), h1 = 2.0 * (d0.x() * D.x() + d0.z() * D.z()),
                 h2 = D.x() * D.x() + D.z() * D.z();
    return {g0 * g0 - 4.0 * R2 * h0, 2.0 * g0 * g1 - 4.0 * R2 * h1, g1 * g1 + 2.0 * g0 * g2 - 4.0 * R2 * h2,
            2.0 * g1 * g2, g2 * g2};
}

}  // namespace isotrace::geometry
