#include "geometry/meshing/mesh_simplifier.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <queue>

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
        compact();
        return collapses;
    }

private:
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
    // onto the surface by Newton steps along the gradient.
    bool placement(uint32_t u, uint32_t v, Vec3& out) const {
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
        for (int i = 0; i < 3; ++i) {
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

    std::vector<uint32_t> neighbours(uint32_t v) const {
        std::vector<uint32_t> out;
        for (uint32_t f : facesOf_[v])
            for (uint32_t w : mesh_.triangles[f])
                if (w != v) out.push_back(w);
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    }

    bool collapseIsValid(uint32_t u, uint32_t v, const Vec3& p) const {
        // Link condition: the only common neighbours are the two opposite
        // vertices of the edge's triangles.
        const std::vector<uint32_t> nu = neighbours(u), nv = neighbours(v);
        std::vector<uint32_t> common;
        std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
        if (common.size() != 2) return false;
        if (nu.size() + nv.size() <= 6) return false;  // would collapse a tetrahedron
        if (distanceToSurface(p) > options_.maxDistance) return false;
        for (uint32_t w : {u, v}) {
            for (uint32_t f : facesOf_[w]) {
                const auto& t = mesh_.triangles[f];
                const bool hasU = t[0] == u || t[1] == u || t[2] == u;
                const bool hasV = t[0] == v || t[1] == v || t[2] == v;
                if (hasU && hasV) continue;  // disappears
                std::array<Vec3, 3> before, after;
                for (int k = 0; k < 3; ++k) {
                    before[k] = mesh_.vertices[t[k]];
                    after[k] = (t[k] == u || t[k] == v) ? p : before[k];
                }
                const Vec3 n0 = (before[1] - before[0]).cross(before[2] - before[0]);
                const Vec3 n1 = (after[1] - after[0]).cross(after[2] - after[0]);
                const double a1 = n1.norm();
                if (!(a1 > 0) || n0.norm() == 0) return false;
                if (n0.normalized().dot(n1 / a1) < options_.minFaceNormalCosine) return false;
                const double longest = std::max({(after[1] - after[0]).squaredNorm(), (after[2] - after[1]).squaredNorm(),
                                                 (after[0] - after[2]).squaredNorm()});
                if (longest / a1 * (std::sqrt(3.0) / 2.0) > options_.maxAspectRatio) return false;
                if (distanceToSurface((after[0] + after[1] + after[2]) / 3.0) > options_.maxDistance) return false;
            }
        }
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
        for (uint32_t w : neighbours(v)) {
            auto& list = facesOf_[w];
            list.erase(std::remove_if(list.begin(), list.end(), [&](uint32_t f) { return removedFace_[f]; }), list.end());
        }
        facesOf_[u] = std::move(kept);
        facesOf_[v].clear();
        // Only edges at u changed cost (its quadric and position); other
        // candidates stay queued and are re-validated when popped.
        ++stamp_[u];
        for (uint32_t w : neighbours(u)) push(u, w);
    }

    void push(uint32_t a, uint32_t b) {
        Vec3 p;
        if (!placement(a, b, p)) return;
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
};

}  // namespace

size_t simplifyMesh(IndexedMesh& mesh, const FieldProgram& field, const SimplifyOptions& options) {
    if (mesh.triangles.empty()) return 0;
    return Simplifier(mesh, field, options).run();
}

}  // namespace isotrace::geometry
