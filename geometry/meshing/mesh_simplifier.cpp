#include "geometry/meshing/mesh_simplifier.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <queue>

#include "geometry/meshing/mesh_analysis.h"

namespace isotrace::geometry {

namespace {

using Quadric = Eigen::Matrix4d;

struct Candidate {
    double cost;
    uint32_t u, v;
    uint32_t stampU, stampV;
    bool operator>(const Candidate& o) const { return cost > o.cost; }
};

class Simplifier {
public:
    Simplifier(IndexedMesh& mesh, const FieldProgram& field, const SimplifyOptions& options)
        : mesh_(mesh), field_(field), options_(options) {
        const size_t n = mesh.vertices.size();
        facesOf_.resize(n);
        quadric_.assign(n, Quadric::Zero());
        stamp_.assign(n, 0);
        removedVertex_.assign(n, false);
        removedFace_.assign(mesh.triangles.size(), false);
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            const Quadric q = faceQuadric(f);
            for (uint32_t v : mesh.triangles[f]) {
                facesOf_[v].push_back(f);
                quadric_[v] += q;
            }
        }
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
                if (a < b) push(a, b);
            }
    }

    size_t run() {
        size_t collapses = 0;
        while (!queue_.empty()) {
            const Candidate c = queue_.top();
            queue_.pop();
            if (removedVertex_[c.u] || removedVertex_[c.v] || stamp_[c.u] != c.stampU || stamp_[c.v] != c.stampV) continue;
            Vec3 position;
            if (!placement(c.u, c.v, position)) continue;
            if (!collapseIsValid(c.u, c.v, position)) continue;
            collapse(c.u, c.v, position);
            ++collapses;
        }
        collapses += removeSlivers();
        compact();
        return collapses;
    }

private:
    double aspectRatio(uint32_t f) const {
        const auto& t = mesh_.triangles[f];
        return triangleAspectRatio(mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]);
    }

    // Slivers left once no collapse lowers the quadric error (marching cubes
    // makes them where the surface passes near a grid corner): a needle loses
    // its shortest edge, a cap has its longest edge flipped, each only when
    // the tolerance, the topology and the faces' orientation still hold.
    size_t removeSlivers() {
        size_t changes = 0;
        for (int round = 0; round < 4; ++round) {
            size_t changed = 0;
            for (uint32_t f = 0; f < mesh_.triangles.size(); ++f) {
                if (removedFace_[f] || !(aspectRatio(f) > options_.maxAspectRatio)) continue;
                const auto t = mesh_.triangles[f];
                int shortest = 0, longest = 0;
                double lengths[3];
                for (int k = 0; k < 3; ++k) {
                    lengths[k] = (mesh_.vertices[t[(k + 1) % 3]] - mesh_.vertices[t[k]]).squaredNorm();
                    if (lengths[k] < lengths[shortest]) shortest = k;
                    if (lengths[k] > lengths[longest]) longest = k;
                }
                const uint32_t u = t[shortest], v = t[(shortest + 1) % 3];
                Vec3 position;
                if (placement(u, v, position) && collapseIsValid(u, v, position)) {
                    collapse(u, v, position);
                    ++changed;
                } else if (flip(t[longest], t[(longest + 1) % 3])) {
                    ++changed;
                }
            }
            changes += changed;
            if (changed == 0) break;
        }
        return changes;
    }

    // Replaces the edge a-b of triangles (a, b, c) and (b, a, d) by c-d, if
    // that makes the worse of the two triangles better and keeps the mesh
    // manifold, oriented, unfolded and within the tolerance.
    bool flip(uint32_t a, uint32_t b) {
        uint32_t f1 = UINT32_MAX, f2 = UINT32_MAX, c = 0, d = 0;
        for (uint32_t f : facesOf_[a]) {
            const auto& t = mesh_.triangles[f];
            for (int k = 0; k < 3; ++k) {
                if (t[k] == a && t[(k + 1) % 3] == b) f1 = f, c = t[(k + 2) % 3];
                if (t[k] == b && t[(k + 1) % 3] == a) f2 = f, d = t[(k + 2) % 3];
            }
        }
        if (f1 == UINT32_MAX || f2 == UINT32_MAX || c == d) return false;
        for (uint32_t f : facesOf_[c])
            for (uint32_t w : mesh_.triangles[f])
                if (w == d) return false;  // c-d exists already: the flip would make a non-manifold edge
        const Vec3 &pa = mesh_.vertices[a], &pb = mesh_.vertices[b], &pc = mesh_.vertices[c], &pd = mesh_.vertices[d];
        const double before = std::max(triangleAspectRatio(pa, pb, pc), triangleAspectRatio(pb, pa, pd));
        const double after = std::max(triangleAspectRatio(pa, pd, pc), triangleAspectRatio(pd, pb, pc));
        if (!(after < before)) return false;
        const Vec3 m1 = (pd - pa).cross(pc - pa), m2 = (pb - pd).cross(pc - pd);
        for (const Vec3& m : {m1, m2}) {
            if (!(m.norm() > 0)) return false;
            if (!keepsOrientation({pa, pb, pc}, m) || !keepsOrientation({pb, pa, pd}, m)) return false;
        }
        if (distanceToSurface((pa + pd + pc) / 3.0) > options_.maxDistance ||
            distanceToSurface((pd + pb + pc) / 3.0) > options_.maxDistance)
            return false;
        mesh_.triangles[f1] = {a, d, c};
        mesh_.triangles[f2] = {d, b, c};
        auto drop = [&](uint32_t v, uint32_t f) {
            auto& list = facesOf_[v];
            list.erase(std::remove(list.begin(), list.end(), f), list.end());
        };
        drop(a, f2);
        drop(b, f1);
        facesOf_[c].push_back(f2);
        facesOf_[d].push_back(f1);
        ++stamp_[a], ++stamp_[b], ++stamp_[c], ++stamp_[d];
        return true;
    }

    // A face replacing `before` with normal n does not turn over: it faces
    // the old face's way, or, where the old face is a sliver whose normal is
    // mostly rounding, the surface's own normal (the field's gradient).
    bool keepsOrientation(const std::array<Vec3, 3>& before, const Vec3& n) const {
        const Vec3 unit = n.normalized();
        if (triangleAspectRatio(before[0], before[1], before[2]) <= options_.maxAspectRatio) {
            const Vec3 n0 = (before[1] - before[0]).cross(before[2] - before[0]);
            return n0.normalized().dot(unit) >= options_.minFaceNormalCosine;
        }
        Vec3 g;
        field_.valueAndGradient((before[0] + before[1] + before[2]) / 3.0, g);
        return g.norm() > 0 && g.normalized().dot(unit) >= options_.minFaceNormalCosine;
    }

    Quadric faceQuadric(uint32_t f) const {
        const auto& t = mesh_.triangles[f];
        const Vec3 n = (mesh_.vertices[t[1]] - mesh_.vertices[t[0]]).cross(mesh_.vertices[t[2]] - mesh_.vertices[t[0]]);
        const double area2 = n.norm();
        if (!(area2 > 0)) return Quadric::Zero();
        const Vec3 unit = n / area2;
        const Eigen::Vector4d plane(unit.x(), unit.y(), unit.z(), -unit.dot(mesh_.vertices[t[0]]));
        return 0.5 * area2 * plane * plane.transpose();  // area weighted
    }

    double distanceToSurface(const Vec3& p) const {
        Vec3 g;
        const double f = field_.valueAndGradient(p, g);
        const double n = g.norm();
        return n > 0 ? std::abs(f) / n : std::abs(f);
    }

    // Quadric minimum (or the best of the ends and the midpoint), projected
    // onto the surface by Newton steps along the gradient unless only its
    // cost is wanted (queueing: the projection is made when the edge is
    // popped, and costs field evaluations for every edge around every
    // collapse).
    bool placement(uint32_t u, uint32_t v, Vec3& out, bool project = true) const {
        const Quadric q = quadric_[u] + quadric_[v];
        const Vec3 &pu = mesh_.vertices[u], &pv = mesh_.vertices[v];
        auto error = [&](const Vec3& p) { return p.homogeneous().dot(q * p.homogeneous()); };
        Vec3 best = 0.5 * (pu + pv);
        const Eigen::Matrix3d A = q.topLeftCorner<3, 3>();
        const Eigen::FullPivLU<Eigen::Matrix3d> lu(A);
        if (lu.rank() == 3) {
            const Vec3 x = lu.solve(-q.topRightCorner<3, 1>());
            // Stay near the edge: a far minimum means an ill-conditioned quadric.
            if ((x - best).norm() < 2.0 * (pu - pv).norm()) best = x;
        }
        for (const Vec3& p : {pu, pv})
            if (error(p) < error(best)) best = p;
        for (int i = 0; project && i < 3; ++i) {
            Vec3 g;
            const double f = field_.valueAndGradient(best, g);
            const double g2 = g.squaredNorm();
            if (!(g2 > 0)) break;
            best -= (f / g2) * g;
        }
        if (!best.allFinite()) return false;
        out = best;
        return true;
    }

    // The vertices sharing a face with v, sorted, into `out` (reused
    // buffers: the simplifier asks this for every candidate collapse).
    void neighbours(uint32_t v, std::vector<uint32_t>& out) const {
        out.clear();
        for (uint32_t f : facesOf_[v])
            for (uint32_t w : mesh_.triangles[f])
                if (w != v) out.push_back(w);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
    }

    bool collapseIsValid(uint32_t u, uint32_t v, const Vec3& p) const {
        // Link condition: the only common neighbours are the two opposite
        // vertices of the edge's triangles.
        std::vector<uint32_t>&nu = scratchU_, &nv = scratchV_;
        neighbours(u, nu);
        neighbours(v, nv);
        size_t common = 0;
        for (size_t i = 0, j = 0; i < nu.size() && j < nv.size();) {
            if (nu[i] < nv[j]) ++i;
            else if (nv[j] < nu[i]) ++j;
            else ++common, ++i, ++j;
        }
        if (common != 2) return false;
        if (nu.size() + nv.size() <= 6) return false;  // would collapse a tetrahedron
        if (distanceToSurface(p) > options_.maxDistance) return false;
        // Refuse making a sliver, not replacing one by a lesser one: the
        // worst face around the edge after must be fine or better than the
        // worst before (marching cubes leaves fans of slivers at grid corners,
        // where a test face by face refuses every collapse).
        double worstBefore = 0.0, worstAfter = 0.0;
        for (uint32_t w : {u, v}) {
            for (uint32_t f : facesOf_[w]) {
                const auto& t = mesh_.triangles[f];
                const bool hasU = t[0] == u || t[1] == u || t[2] == u;
                const bool hasV = t[0] == v || t[1] == v || t[2] == v;
                worstBefore = std::max(worstBefore, aspectRatio(f));
                if (hasU && hasV) continue;  // disappears
                std::array<Vec3, 3> before, after;
                for (int k = 0; k < 3; ++k) {
                    before[k] = mesh_.vertices[t[k]];
                    after[k] = (t[k] == u || t[k] == v) ? p : before[k];
                }
                const Vec3 n1 = (after[1] - after[0]).cross(after[2] - after[0]);
                if (!(n1.norm() > 0)) return false;
                if (!keepsOrientation(before, n1)) return false;
                worstAfter = std::max(worstAfter, triangleAspectRatio(after[0], after[1], after[2]));
                if (distanceToSurface((after[0] + after[1] + after[2]) / 3.0) > options_.maxDistance) return false;
            }
        }
        if (worstAfter > options_.maxAspectRatio && !(worstAfter < worstBefore)) return false;
        return true;
    }

    void collapse(uint32_t u, uint32_t v, const Vec3& p) {
        mesh_.vertices[u] = p;
        quadric_[u] += quadric_[v];
        removedVertex_[v] = true;
        std::vector<uint32_t> kept;
        for (uint32_t f : facesOf_[u]) {
            const auto& t = mesh_.triangles[f];
            if (t[0] == v || t[1] == v || t[2] == v) removedFace_[f] = true;
            else kept.push_back(f);
        }
        for (uint32_t f : facesOf_[v]) {
            if (removedFace_[f]) continue;
            auto& t = mesh_.triangles[f];
            if (t[0] == u || t[1] == u || t[2] == u) {
                removedFace_[f] = true;
                continue;
            }
            for (uint32_t& w : t)
                if (w == v) w = u;
            kept.push_back(f);
        }
        // Faces removed above may still sit in other vertices' lists.
        neighbours(v, scratchU_);
        for (uint32_t w : scratchU_) {
            auto& list = facesOf_[w];
            list.erase(std::remove_if(list.begin(), list.end(), [&](uint32_t f) { return removedFace_[f]; }), list.end());
        }
        facesOf_[u] = std::move(kept);
        facesOf_[v].clear();
        // Only edges at u changed cost (its quadric and position); other
        // candidates stay queued and are re-validated when popped.
        ++stamp_[u];
        neighbours(u, scratchU_);
        for (uint32_t w : scratchU_) push(u, w);
    }

    void push(uint32_t a, uint32_t b) {
        Vec3 p;
        if (!placement(a, b, p, false)) return;
        const Quadric q = quadric_[a] + quadric_[b];
        queue_.push({std::max(0.0, p.homogeneous().dot(q * p.homogeneous())), a, b, stamp_[a], stamp_[b]});
    }

    void compact() {
        std::vector<uint32_t> remap(mesh_.vertices.size(), UINT32_MAX);
        IndexedMesh out;
        for (uint32_t f = 0; f < mesh_.triangles.size(); ++f) {
            if (removedFace_[f]) continue;
            std::array<uint32_t, 3> t;
            for (int k = 0; k < 3; ++k) {
                uint32_t& r = remap[mesh_.triangles[f][k]];
                if (r == UINT32_MAX) {
                    r = uint32_t(out.vertices.size());
                    const Vec3& p = mesh_.vertices[mesh_.triangles[f][k]];
                    out.vertices.push_back(p);
                    Vec3 g;
                    field_.valueAndGradient(p, g);
                    out.normals.push_back(g.norm() > 0 ? Vec3(g.normalized()) : Vec3(0, 1, 0));
                }
                t[k] = r;
            }
            out.triangles.push_back(t);
        }
        mesh_ = std::move(out);
    }

    IndexedMesh& mesh_;
    const FieldProgram& field_;
    SimplifyOptions options_;
    std::vector<std::vector<uint32_t>> facesOf_;
    std::vector<Quadric> quadric_;
    std::vector<uint32_t> stamp_;
    std::vector<bool> removedVertex_, removedFace_;
    std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> queue_;
    mutable std::vector<uint32_t> scratchU_, scratchV_;  ///< neighbour lists, reused
};

}  // namespace

size_t simplifyMesh(IndexedMesh& mesh, const FieldProgram& field, const SimplifyOptions& options) {
    if (mesh.triangles.empty()) return 0;
    return Simplifier(mesh, field, options).run();
}

}  // namespace isotrace::geometry
