#include "geometry/meshing/mesh_simplifier.h"

#include <tbb/parallel_for.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "geometry/meshing/cost_buckets.h"
#include "geometry/meshing/mesh_analysis.h"
#include "geometry/meshing/vertex_fans.h"

namespace isotrace::geometry {

namespace {

// Garland and Heckbert's quadric as its ten distinct entries: the weighted
// sum of squared distances to planes, error(p) = pᵀAp + 2bᵀp + c.
struct Quadric {
    // No initialisers: the simplifier's array of them is filled in parallel
    // (Quadric() and Quadric{} are zero).
    double a00, a01, a02, a11, a12, a22, b0, b1, b2, c;

    /// The plane n·p + d = 0 (n of unit length), weighted.
    static Quadric ofPlane(const Vec3& n, double d, double weight) {
        Quadric q{};
        q.a00 = weight * n.x() * n.x(), q.a01 = weight * n.x() * n.y(), q.a02 = weight * n.x() * n.z();
        q.a11 = weight * n.y() * n.y(), q.a12 = weight * n.y() * n.z(), q.a22 = weight * n.z() * n.z();
        q.b0 = weight * d * n.x(), q.b1 = weight * d * n.y(), q.b2 = weight * d * n.z();
        q.c = weight * d * d;
        return q;
    }

    Quadric& operator+=(const Quadric& o) {
        a00 += o.a00, a01 += o.a01, a02 += o.a02, a11 += o.a11, a12 += o.a12, a22 += o.a22;
        b0 += o.b0, b1 += o.b1, b2 += o.b2, c += o.c;
        return *this;
    }
    friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }

    double error(const Vec3& p) const {
        const double x = p.x(), y = p.y(), z = p.z();
        return x * (a00 * x + 2.0 * (a01 * y + a02 * z + b0)) + y * (a11 * y + 2.0 * (a12 * z + b1)) +
               z * (a22 * z + 2.0 * b2) + c;
    }

    /// The minimiser A⁻¹(−b) by the adjugate, unless A is near singular
    /// (a flat or cylindrical neighbourhood: no unique minimum).
    bool minimum(Vec3& out) const {
        const double c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22, c02 = a01 * a12 - a02 * a11;
        const double det = a00 * c00 + a01 * c01 + a02 * c02;
        const double trace = a00 + a11 + a22;
        if (!(std::abs(det) > 1e-12 * trace * trace * trace)) return false;
        const double c11 = a00 * a22 - a02 * a02, c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
        out = Vec3(c00 * b0 + c01 * b1 + c02 * b2, c01 * b0 + c11 * b1 + c12 * b2, c02 * b0 + c12 * b1 + c22 * b2) / -det;
        return true;
    }
};

// A queued collapse, 16 bytes: the queue is the simplifier's busiest
// memory. Stamps only grow, so their sum changes whenever either end
// changed after the candidate was queued.
struct Candidate {
    float cost;
    uint32_t u, v;
    uint32_t stamps;
};

constexpr uint32_t kAnyBlock = UINT32_MAX;

// One queue of candidate collapses and its scratch lists. A block's worker
// collapses only edges whose surrounding faces all lie in its block.
struct Worker {
    uint32_t block = kAnyBlock;
    CostBuckets<Candidate> queue;
    std::vector<uint32_t> kept;
    uint32_t generation = 0;  ///< the last mark this worker gave a vertex
    std::vector<Vec3> centroids;  ///< of each new face, those that moved farthest first
};

// A queue is given up after this many refused collapses in a row: costs
// only rise as it drains, and on a curved surface refined to just within
// the tolerance most late collapses fail. Almost every collapse is still
// made (bench/polygonize_throughput; bench/RESULTS.md, "Tuned constants").
constexpr size_t kMaxFailuresInARow = 256;

// Blocks hold about this many vertices (up to 4 x 4 x 4 of them): enough
// work per block to hide scheduling, and walls thin against the block.
constexpr double kVerticesPerBlock = 4096.0;
constexpr int kMaxBlocksPerAxis = 4;

// A point placed on the surface and the field's gradient there.
struct SurfacePoint {
    Vec3 position, gradient;
};

class Simplifier {
public:
    Simplifier(IndexedMesh& mesh, const FieldProgram& field, const SimplifyOptions& options)
        : mesh_(mesh), field_(field), options_(options), facesOf_(mesh.vertices.size()) {
        const size_t n = mesh.vertices.size();
        // Normals given with every vertex are kept and moved with it (the
        // field's, as marching cubes and refinement leave them); otherwise
        // compact() takes them from the field.
        if (mesh.normals.size() != n) mesh.normals.clear();
        quadric_.reset(new Quadric[n]);  // written by buildAdjacency
        stamp_.assign(n, 0);
        removedVertex_.assign(n, 0);
        deferred_.assign(n, 0);
        interior_.assign(n, 0);
        mark_.assign(n, 0);
        removedFace_.assign(mesh.triangles.size(), 0);
    }

    size_t run() {
        size_t total = 0;
        tbb::task_arena arena(options_.threads > 0 ? options_.threads : tbb::task_arena::automatic);
        const BlockGrid grid = blockGrid();
        arena.execute([&] {
            renumberByBlock(grid);
            buildAdjacency();
        });
        // Two rounds over blocks, the second on a grid shifted by half a
        // block and seeded with the edges the first had to leave, so that
        // only edges near the walls of both grids wait for the whole mesh.
        std::vector<uint8_t> seed(mesh_.vertices.size(), 1);
        tbb::enumerable_thread_specific<Worker> workers;
        for (double shift : {0.0, 0.5}) {
            std::vector<std::vector<uint32_t>> seedsOf;
            arena.execute([&] { seedsOf = assignBlocks(grid, shift, seed); });
            std::fill(deferred_.begin(), deferred_.end(), 0);
            std::fill(mark_.begin(), mark_.end(), 0);
            std::vector<size_t> collapses(seedsOf.size(), 0);
            // Each block owns its vertices and the faces wholly inside it,
            // so no two workers touch the same data.
            arena.execute([&] {
                tbb::parallel_for(size_t(0), seedsOf.size(), [&](size_t b) {
                    // One worker per thread, reused: its queue's buckets
                    // keep their capacity from block to block.
                    Worker& worker = workers.local();
                    worker.block = uint32_t(b);
                    // The block's vertices have never been marked this round.
                    worker.generation = 0;
                    for (uint32_t u : seedsOf[b]) {
                        if (!interior_[u]) {
                            deferred_[u] = 1;
                            continue;
                        }
                        forEachNeighbour(worker, u, [&](uint32_t w) {
                            if (interior_[w] && (!seed[w] || u < w)) push(worker, u, w);
                        });
                    }
                    collapses[b] = drain(worker);
                });
            });
            for (size_t c : collapses) total += c;
            seed.swap(deferred_);
        }
        Worker whole;
        std::fill(mark_.begin(), mark_.end(), 0);
        for (uint32_t u = 0; u < mesh_.vertices.size(); ++u) {
            if (!seed[u] || removedVertex_[u]) continue;
            forEachNeighbour(whole, u, [&](uint32_t w) {
                if (!seed[w] || u < w) push(whole, u, w);
            });
        }
        total += drain(whole);
        total += removeSlivers(whole);
        arena.execute([&] { compact(); });
        return total;
    }

private:
    // The faces around each vertex, in the order of the faces (one pass over
    // them, appending to each vertex's record: no counting pass, no
    // temporary lists), then each vertex's quadric, the sum of its faces',
    // in parallel.
    void buildAdjacency() {
        const size_t n = mesh_.vertices.size();
        tbb::parallel_for(size_t(0), n, [&](size_t v) { facesOf_.clear(uint32_t(v)); });
        for (uint32_t f = 0; f < mesh_.triangles.size(); ++f)
            for (uint32_t v : mesh_.triangles[f]) facesOf_.pushBack(v, f);
        aspect_.resize(mesh_.triangles.size());
        tbb::parallel_for(size_t(0), mesh_.triangles.size(), [&](size_t f) { aspect_[f] = computeAspectRatio(uint32_t(f)); });
        tbb::parallel_for(size_t(0), n, [&](size_t v) {
            Quadric q{};
            for (uint32_t f : facesOf_[v]) q += faceQuadric(f);
            quadric_[v] = q;
        });
    }

    struct BlockGrid {
        Vec3 lo, cellsPerUnit;
        int perAxis;
    };

    // A grid over the vertices' bounding box with blocks of about
    // kVerticesPerBlock vertices.
    BlockGrid blockGrid() const {
        Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
        for (const Vec3& p : mesh_.vertices) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
        const int perAxis = std::clamp(int(std::lround(std::cbrt(double(mesh_.vertices.size()) / kVerticesPerBlock))), 1,
                                       kMaxBlocksPerAxis);
        return {lo, (double(perAxis) / (hi - lo).array().max(1e-300)).matrix(), perAxis};
    }

    // The block of point p in the grid shifted by `shift` blocks.
    static uint32_t blockOf(const BlockGrid& grid, double shift, const Vec3& p) {
        const int cells = grid.perAxis + (shift > 0 ? 1 : 0);
        int cell[3];
        for (int k = 0; k < 3; ++k)
            cell[k] = std::clamp(int((p[k] - grid.lo[k]) * grid.cellsPerUnit[k] + shift), 0, cells - 1);
        return uint32_t((cell[0] * cells + cell[1]) * cells + cell[2]);
    }

    // Numbers the vertices block by block, and the faces by the block of
    // their first vertex, keeping the order within each block (called inside
    // the task arena). Numbered as refinement left them, a block's vertices
    // and faces were lines scattered over the whole mesh's arrays; now each
    // block reads its own few hundred kilobytes. On the sphere of
    // bench/polygonize_throughput the renumbering takes 4 ms and saves 5 ms
    // building the fans and quadrics and 5 ms in the first round (medians of
    // 50 runs: simplification 155 -> 149 ms).
    void renumberByBlock(const BlockGrid& grid) {
        const size_t n = mesh_.vertices.size(), faces = mesh_.triangles.size();
        const size_t blocks = size_t(grid.perAxis) * grid.perAxis * grid.perAxis;
        if (blocks == 1) return;
        // A counting sort, stable: the keys in parallel, the offsets in one
        // sequential pass, the moves in parallel.
        auto sortByKey = [blocks](std::vector<uint32_t>& keyToPlace) {
            std::vector<uint32_t> next(blocks + 1, 0);
            for (uint32_t k : keyToPlace) ++next[k + 1];
            for (size_t b = 1; b <= blocks; ++b) next[b] += next[b - 1];
            for (uint32_t& k : keyToPlace) k = next[k]++;
        };
        std::vector<uint32_t> block(n), number(n);
        tbb::parallel_for(size_t(0), n,
                          [&](size_t v) { number[v] = block[v] = blockOf(grid, 0.0, mesh_.vertices[v]); });
        sortByKey(number);
        std::vector<Vec3> vertices(n);
        tbb::parallel_for(size_t(0), n, [&](size_t v) { vertices[number[v]] = mesh_.vertices[v]; });
        mesh_.vertices.swap(vertices);
        if (!mesh_.normals.empty()) {
            tbb::parallel_for(size_t(0), n, [&](size_t v) { vertices[number[v]] = mesh_.normals[v]; });
            mesh_.normals.swap(vertices);
        }
        std::vector<uint32_t> place(faces);
        tbb::parallel_for(size_t(0), faces, [&](size_t f) { place[f] = block[mesh_.triangles[f][0]]; });
        sortByKey(place);
        std::vector<std::array<uint32_t, 3>> triangles(faces);
        tbb::parallel_for(size_t(0), faces, [&](size_t f) {
            const auto& t = mesh_.triangles[f];
            triangles[place[f]] = {number[t[0]], number[t[1]], number[t[2]]};
        });
        mesh_.triangles.swap(triangles);
    }

    // Every live vertex's block in the grid shifted by `shift` blocks; the
    // seeds of each block in a list.
    std::vector<std::vector<uint32_t>> assignBlocks(const BlockGrid& grid, double shift, const std::vector<uint8_t>& seed) {
        const int cells = grid.perAxis + (shift > 0 ? 1 : 0);
        std::vector<std::vector<uint32_t>> seedsOf(size_t(cells) * cells * cells);
        block_.resize(mesh_.vertices.size());
        tbb::parallel_for(size_t(0), mesh_.vertices.size(),
                          [&](size_t v) { block_[v] = blockOf(grid, shift, mesh_.vertices[v]); });
        for (uint32_t v = 0; v < mesh_.vertices.size(); ++v)
            if (seed[v] && !removedVertex_[v] && !facesOf_.empty(v)) seedsOf[block_[v]].push_back(v);
        // A vertex whose faces lie in its block stays so through the round:
        // its block's collapses only merge neighbourhoods inside the block,
        // and no other block touches it.
        tbb::parallel_for(size_t(0), mesh_.vertices.size(), [&](size_t v) {
            bool inside = true;
            for (uint32_t f : facesOf_[v])
                for (uint32_t x : mesh_.triangles[f]) inside = inside && block_[x] == block_[v];
            interior_[v] = inside;
        });
        return seedsOf;
    }

    // Pops until the queue is empty or kMaxFailuresInARow collapses in a
    // row were refused; what is left is dropped (the worker's queue serves
    // its next block).
    size_t drain(Worker& worker) {
        size_t collapses = 0, failures = 0;
        Candidate c;
        while (worker.queue.pop(c)) {
            if (removedVertex_[c.u] || removedVertex_[c.v] || stamp_[c.u] + stamp_[c.v] != c.stamps) continue;
            if (!ownsNeighbourhood(worker, c.u, c.v)) continue;
            if (++failures > kMaxFailuresInARow) {
                worker.queue.clear();
                break;
            }
            SurfacePoint point;
            if (!placement(c.u, c.v, point)) continue;
            const PreTest pre = likeliestToLeave(c.u, c.v, point.position);
            if (pre.leaves) continue;
            if (!collapseIsValid(worker, c.u, c.v, point.position, pre.checked)) continue;
            collapse(worker, c.u, c.v, point);
            ++collapses;
            failures = 0;
        }
        return collapses;
    }

    // Whether every face around u and v lies in the worker's block; if not,
    // the edge waits for the whole-mesh queue.
    bool ownsNeighbourhood(const Worker& worker, uint32_t u, uint32_t v) {
        if (worker.block == kAnyBlock || (interior_[u] && interior_[v])) return true;
        deferred_[u] = deferred_[v] = 1;
        return false;
    }

    double computeAspectRatio(uint32_t f) const {
        const auto& t = mesh_.triangles[f];
        return triangleAspectRatio(mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]);
    }

    // Slivers left once no collapse lowers the quadric error (marching cubes
    // makes them where the surface passes near a grid corner): a needle loses
    // its shortest edge, a cap has its longest edge flipped, each only when
    // the tolerance, the topology and the faces' orientation still hold.
    size_t removeSlivers(Worker& worker) {
        size_t changes = 0;
        for (int round = 0; round < 4; ++round) {
            size_t changed = 0;
            for (uint32_t f = 0; f < mesh_.triangles.size(); ++f) {
                if (removedFace_[f] || !(aspect_[f] > options_.maxAspectRatio)) continue;
                const auto t = mesh_.triangles[f];
                int shortest = 0, longest = 0;
                double lengths[3];
                for (int k = 0; k < 3; ++k) {
                    lengths[k] = (mesh_.vertices[t[(k + 1) % 3]] - mesh_.vertices[t[k]]).squaredNorm();
                    if (lengths[k] < lengths[shortest]) shortest = k;
                    if (lengths[k] > lengths[longest]) longest = k;
                }
                // A needle loses its shortest edge, a cap has its longest
                // flipped; failing both, the remaining edge is collapsed.
                auto collapseEdge = [&](int k) {
                    const uint32_t u = t[k], v = t[(k + 1) % 3];
                    SurfacePoint point;
                    if (!placement(u, v, point) || !collapseIsValid(worker, u, v, point.position)) return false;
                    collapse(worker, u, v, point);
                    return true;
                };
                if (collapseEdge(shortest) || flip(t[longest], t[(longest + 1) % 3]) ||
                    (shortest != longest && collapseEdge(3 - shortest - longest)))
                    ++changed;
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
        const double aspect1 = triangleAspectRatio(pa, pb, pc), aspect2 = triangleAspectRatio(pb, pa, pd);
        const double after = std::max(triangleAspectRatio(pa, pd, pc), triangleAspectRatio(pd, pb, pc));
        if (!(after < std::max(aspect1, aspect2))) return false;
        const Vec3 m1 = (pd - pa).cross(pc - pa), m2 = (pb - pd).cross(pc - pd);
        for (const Vec3& m : {m1, m2}) {
            if (!(m.norm() > 0)) return false;
            if (!keepsOrientation({pa, pb, pc}, aspect1, m) || !keepsOrientation({pb, pa, pd}, aspect2, m)) return false;
        }
        if (distanceToSurface((pa + pd + pc) / 3.0) > options_.maxDistance ||
            distanceToSurface((pd + pb + pc) / 3.0) > options_.maxDistance)
            return false;
        mesh_.triangles[f1] = {a, d, c};
        mesh_.triangles[f2] = {d, b, c};
        aspect_[f1] = computeAspectRatio(f1);
        aspect_[f2] = computeAspectRatio(f2);
        facesOf_.eraseIf(a, [f2](uint32_t f) { return f == f2; });
        facesOf_.eraseIf(b, [f1](uint32_t f) { return f == f1; });
        facesOf_.pushBack(c, f2);
        facesOf_.pushBack(d, f1);
        ++stamp_[a], ++stamp_[b], ++stamp_[c], ++stamp_[d];
        return true;
    }

    // A face replacing `before` with normal n does not turn over: it faces
    // the old face's way, or, where the old face is a sliver whose normal is
    // mostly rounding, the surface's own normal (the field's gradient).
    bool keepsOrientation(const std::array<Vec3, 3>& before, double aspectBefore, const Vec3& n) const {
        Vec3 reference;
        if (aspectBefore <= options_.maxAspectRatio) reference = (before[1] - before[0]).cross(before[2] - before[0]);
        else field_.valueAndGradient((before[0] + before[1] + before[2]) / 3.0, reference);
        const double lengths = std::sqrt(reference.squaredNorm() * n.squaredNorm());
        return lengths > 0 && reference.dot(n) >= options_.minFaceNormalCosine * lengths;
    }

    Quadric faceQuadric(uint32_t f) const {
        const auto& t = mesh_.triangles[f];
        const Vec3 n = (mesh_.vertices[t[1]] - mesh_.vertices[t[0]]).cross(mesh_.vertices[t[2]] - mesh_.vertices[t[0]]);
        const double area2 = n.norm();
        if (!(area2 > 0)) return Quadric();
        const Vec3 unit = n / area2;
        return Quadric::ofPlane(unit, -unit.dot(mesh_.vertices[t[0]]), 0.5 * area2);  // area weighted
    }

    double distanceToSurface(const Vec3& p) const { return surfaceDistance(field_, p); }

    // The quadric's minimum, where it has one near the edge pa-pb: a far
    // minimum means an ill-conditioned quadric.
    static bool minimumNearEdge(const Quadric& q, const Vec3& pa, const Vec3& pb, Vec3& x) {
        return q.minimum(x) && (x - 0.5 * (pa + pb)).squaredNorm() < 4.0 * (pa - pb).squaredNorm();
    }

    // Quadric minimum (or the best of the ends and the midpoint), projected
    // onto the surface by Newton steps along the gradient. Made when an edge
    // is popped: queueing (candidate) asks only the quadric, since every
    // collapse queues all the edges around its vertex.
    bool placement(uint32_t u, uint32_t v, SurfacePoint& out) const {
        const Quadric q = quadric_[u] + quadric_[v];
        const Vec3 &pu = mesh_.vertices[u], &pv = mesh_.vertices[v];
        Vec3 best = 0.5 * (pu + pv), x;
        if (minimumNearEdge(q, pu, pv, x)) best = x;
        double bestError = q.error(best);
        for (const Vec3& p : {pu, pv}) {
            const double e = q.error(p);
            if (e < bestError) best = p, bestError = e;
        }
        // Up to three Newton steps, fewer once the point is on the surface
        // to well within the tolerance (the quadric minimum of a flat
        // neighbourhood already is); the last evaluation gives the distance.
        double distance = 0.0;
        Vec3 g;
        for (int i = 0;; ++i) {
            const double f = field_.valueAndGradient(best, g);
            const double g2 = g.squaredNorm();
            distance = g2 > 0 ? std::abs(f) / std::sqrt(g2) : std::abs(f);
            if (i == 3 || !(g2 > 0) || distance <= 1e-3 * options_.maxDistance) break;
            best -= (f / g2) * g;
        }
        if (!best.allFinite() || !(distance <= options_.maxDistance)) return false;
        out = {best, g};
        return true;
    }

    // Calls visit(w) once for each vertex w sharing a face with v, marking
    // them with a new worker generation: no list to sort (seeding the queues
    // through sorted lists took 3% of the sphere's adaptive polygonization in
    // bench/polygonize_throughput; ratio to marching cubes 2.16x -> 2.09x).
    template <class Visit>
    void forEachNeighbour(Worker& worker, uint32_t v, Visit visit) const {
        const uint32_t visited = ++worker.generation;
        for (uint32_t f : facesOf_[v])
            for (uint32_t w : mesh_.triangles[f])
                if (w != v && mark_[w] != visited) {
                    mark_[w] = visited;
                    visit(w);
                }
    }

    // The ends of u-v, the one that moves farther to p first: every face of
    // one end moves its centroid by a third of that end's move.
    std::array<uint32_t, 2> byMove(uint32_t u, uint32_t v, const Vec3& p) const {
        if ((p - mesh_.vertices[u]).squaredNorm() >= (p - mesh_.vertices[v]).squaredNorm()) return {u, v};
        return {v, u};
    }

    // Face t once u and v have merged at p. The distance pre-test and
    // collapseIsValid both build new faces here, so they sum the same
    // centroid and the pre-tested face need not be asked again.
    std::array<Vec3, 3> afterCollapse(const std::array<uint32_t, 3>& t, uint32_t u, uint32_t v, const Vec3& p) const {
        std::array<Vec3, 3> after;
        for (int k = 0; k < 3; ++k) after[k] = (t[k] == u || t[k] == v) ? p : mesh_.vertices[t[k]];
        return after;
    }

    static constexpr uint32_t kNoFace = UINT32_MAX;

    // New faces whose centroids were found within the tolerance before the
    // other tests, or that a collapse leaves the tolerance.
    struct PreTest {
        bool leaves = false;
        std::array<uint32_t, 2> checked = {kNoFace, kNoFace};
    };

    // The distance tests of the two new faces likeliest to leave the
    // tolerance, asked before any other test: most collapses tried fail
    // there. A face of the surface's chords lies about Σ edge² / (18 r)
    // from a sphere of radius r at its centroid, so the face with the
    // largest sum of squared edges is asked first; then the first face of
    // the end that moves farther (whose centroids move most). On the sphere
    // of bench/polygonize_throughput the second alone caught 72k of 163k
    // failing collapses, the first alone 159k; on the tangle the first
    // alone left 43k of 126k to fail after every geometric test.
    PreTest likeliestToLeave(uint32_t u, uint32_t v, const Vec3& p) const {
        PreTest result;
        const uint32_t far = byMove(u, v, p)[0];
        double largest = -1.0;
        Vec3 centroids[2];
        for (uint32_t end : {u, v})
            for (uint32_t f : facesOf_[end]) {
                const auto& t = mesh_.triangles[f];
                const uint32_t other = end == u ? v : u;
                if (t[0] == other || t[1] == other || t[2] == other) continue;  // disappears
                const std::array<Vec3, 3> after = afterCollapse(t, u, v, p);
                const double edges = (after[1] - after[0]).squaredNorm() + (after[2] - after[1]).squaredNorm() +
                                     (after[0] - after[2]).squaredNorm();
                const Vec3 centroid = (after[0] + after[1] + after[2]) / 3.0;
                if (edges > largest) largest = edges, result.checked[0] = f, centroids[0] = centroid;
                if (end == far && result.checked[1] == kNoFace) result.checked[1] = f, centroids[1] = centroid;
            }
        if (result.checked[1] == result.checked[0]) result.checked[1] = kNoFace;
        for (int k = 0; k < 2; ++k)
            if (result.checked[k] != kNoFace && distanceToSurface(centroids[k]) > options_.maxDistance) {
                result.leaves = true;
                break;
            }
        return result;
    }

    // `checked`: new faces whose centroids are known to be within the
    // tolerance already.
    bool collapseIsValid(Worker& worker, uint32_t u, uint32_t v, const Vec3& p,
                         std::array<uint32_t, 2> checked = {kNoFace, kNoFace}) const {
        // Link condition: the only common neighbours are the two opposite
        // vertices of the edge's triangles. Neighbours are marked with
        // worker generations (each vertex belongs to one worker per round).
        const uint32_t aroundU = ++worker.generation, seen = ++worker.generation;
        size_t degreeU = 0, degreeV = 0, common = 0;
        for (uint32_t f : facesOf_[u])
            for (uint32_t w : mesh_.triangles[f])
                if (w != u && mark_[w] != aroundU) mark_[w] = aroundU, ++degreeU;
        for (uint32_t f : facesOf_[v])
            for (uint32_t w : mesh_.triangles[f]) {
                if (w == v || mark_[w] == seen) continue;
                if (mark_[w] == aroundU) ++common;
                mark_[w] = seen, ++degreeV;
            }
        if (common != 2) return false;
        if (degreeU + degreeV <= 6) return false;  // would collapse a tetrahedron
        // Refuse making a sliver, not replacing one by a lesser one: the
        // worst face around the edge after must be fine or better than the
        // worst before (marching cubes leaves fans of slivers at grid corners,
        // where a test face by face refuses every collapse).
        // The field is asked last, for the faces that pass the geometric
        // tests: most refusals are geometric and cost no evaluation.
        double worstBefore = 0.0, worstAfter = 0.0;
        auto& centroids = worker.centroids;
        centroids.clear();
        // The faces of the end that moves farther come first, as the
        // likeliest to leave the tolerance.
        for (uint32_t w : byMove(u, v, p)) {
            for (uint32_t f : facesOf_[w]) {
                const auto& t = mesh_.triangles[f];
                const bool hasU = t[0] == u || t[1] == u || t[2] == u;
                const bool hasV = t[0] == v || t[1] == v || t[2] == v;
                const std::array<Vec3, 3> before = {mesh_.vertices[t[0]], mesh_.vertices[t[1]], mesh_.vertices[t[2]]};
                const std::array<Vec3, 3> after = afterCollapse(t, u, v, p);
                const double aspectBefore = aspect_[f];
                worstBefore = std::max(worstBefore, aspectBefore);
                if (hasU && hasV) continue;  // disappears
                const Vec3 e0 = after[1] - after[0], e1 = after[2] - after[1], e2 = after[0] - after[2];
                const Vec3 n1 = e0.cross(-e2);
                const double area2 = n1.norm();
                if (!(area2 > 0)) return false;
                if (!keepsOrientation(before, aspectBefore, n1)) return false;
                // triangleAspectRatio, with the cross product above
                const double longest = std::max({e0.squaredNorm(), e1.squaredNorm(), e2.squaredNorm()});
                worstAfter = std::max(worstAfter, longest / area2 * (std::sqrt(3.0) / 2.0));
                if (f != checked[0] && f != checked[1]) centroids.push_back((after[0] + after[1] + after[2]) / 3.0);
            }
        }
        if (worstAfter > options_.maxAspectRatio && !(worstAfter < worstBefore)) return false;
        for (size_t i = 0; i < centroids.size(); ++i)
            if (distanceToSurface(centroids[i]) > options_.maxDistance) return false;
        return true;
    }

    void collapse(Worker& worker, uint32_t u, uint32_t v, const SurfacePoint& point) {
        mesh_.vertices[u] = point.position;
        if (!mesh_.normals.empty()) mesh_.normals[u] = vertexNormal(point.gradient);
        quadric_[u] += quadric_[v];
        removedVertex_[v] = 1;
        std::vector<uint32_t>& kept = worker.kept;
        kept.clear();
        for (uint32_t f : facesOf_[u]) {
            const auto& t = mesh_.triangles[f];
            if (t[0] == v || t[1] == v || t[2] == v) removedFace_[f] = 1;
            else kept.push_back(f);
        }
        for (uint32_t f : facesOf_[v]) {
            if (removedFace_[f]) continue;
            auto& t = mesh_.triangles[f];
            if (t[0] == u || t[1] == u || t[2] == u) {
                removedFace_[f] = 1;
                continue;
            }
            for (uint32_t& w : t)
                if (w == v) w = u;
            kept.push_back(f);
        }
        // The removed faces (those holding both u and v) still sit in the
        // lists of their third vertices.
        for (uint32_t f : facesOf_[v]) {
            if (!removedFace_[f]) continue;
            for (uint32_t w : mesh_.triangles[f]) {
                if (w == u || w == v) continue;
                facesOf_.eraseIf(w, [&](uint32_t g) { return removedFace_[g] != 0; });
            }
        }
        facesOf_.assign(u, kept);
        facesOf_.clear(v);
        for (uint32_t f : facesOf_[u]) aspect_[f] = computeAspectRatio(f);
        // Only edges at u changed cost (its quadric and position); other
        // candidates stay queued and are re-validated when popped.
        ++stamp_[u];
        forEachNeighbour(worker, u, [&](uint32_t w) { push(worker, u, w); });
    }

    // The queue's key: the quadric error at the best of the edge's midpoint
    // and ends, not at the quadric's minimum (the placement made when the
    // edge is popped still takes the minimum). No 3x3 solve per queued edge,
    // and an order that tries first the edges a collapse changes least: on
    // bench/polygonize_throughput the simplification took 11% less time on
    // the sphere (0.150 -> 0.133 s), 9% on the tangle, 5% on the cube minus a
    // ball, and left 0.2%, 1.1% and 2.8% fewer triangles.
    bool candidate(uint32_t a, uint32_t b, Candidate& c) const {
        const Quadric q = quadric_[a] + quadric_[b];
        const Vec3 &pa = mesh_.vertices[a], &pb = mesh_.vertices[b];
        const double cost = std::min({q.error(0.5 * (pa + pb)), q.error(pa), q.error(pb)});
        if (!std::isfinite(cost)) return false;
        c = {float(std::max(0.0, cost)), a, b, stamp_[a] + stamp_[b]};
        return true;
    }

    void push(Worker& worker, uint32_t a, uint32_t b) const {
        if (Candidate c; candidate(a, b, c)) worker.queue.push(c);
    }

    // Drops removed faces and vertices, keeping the order of the rest (the
    // vertices' is the blocks'); normals kept, or else from the field. All
    // in parallel (called inside the task arena): serial, the first-use
    // numbering took 5 of the sphere's 8 ms here.
    void compact() {
        const size_t n = mesh_.vertices.size(), faces = mesh_.triangles.size();
        std::vector<uint32_t> vertexIndex(n), faceIndex(faces);
        // A vertex stays while faces use it; its fan lists them.
        const size_t vertices = keptIndices(n, [&](size_t v) { return !facesOf_.empty(uint32_t(v)); }, vertexIndex);
        const size_t kept = keptIndices(faces, [&](size_t f) { return removedFace_[f] == 0; }, faceIndex);
        IndexedMesh out;
        out.vertices.resize(vertices);
        out.normals.resize(vertices);
        out.triangles.resize(kept);
        const bool normalsKept = !mesh_.normals.empty();
        tbb::parallel_for(size_t(0), n, [&](size_t v) {
            if (facesOf_.empty(uint32_t(v))) return;
            const Vec3& p = mesh_.vertices[v];
            out.vertices[vertexIndex[v]] = p;
            if (normalsKept) {
                out.normals[vertexIndex[v]] = mesh_.normals[v];
            } else {
                Vec3 g;
                field_.valueAndGradient(p, g);
                out.normals[vertexIndex[v]] = vertexNormal(g);
            }
        });
        tbb::parallel_for(size_t(0), faces, [&](size_t f) {
            if (removedFace_[f]) return;
            const auto& t = mesh_.triangles[f];
            out.triangles[faceIndex[f]] = {vertexIndex[t[0]], vertexIndex[t[1]], vertexIndex[t[2]]};
        });
        mesh_ = std::move(out);
    }

    // index[i]: how many i' < i are kept, for each kept i; returns how many
    // are kept. Counts by chunk in parallel, then numbers each chunk from
    // its offset in parallel.
    template <class Kept>
    static size_t keptIndices(size_t count, Kept kept, std::vector<uint32_t>& index) {
        constexpr size_t kChunk = 16384;
        const size_t chunks = (count + kChunk - 1) / kChunk;
        std::vector<size_t> offset(chunks + 1, 0);
        tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
            size_t k = 0;
            for (size_t i = c * kChunk; i < std::min(count, (c + 1) * kChunk); ++i) k += kept(i) ? 1 : 0;
            offset[c + 1] = k;
        });
        for (size_t c = 0; c < chunks; ++c) offset[c + 1] += offset[c];
        tbb::parallel_for(size_t(0), chunks, [&](size_t c) {
            uint32_t next = uint32_t(offset[c]);
            for (size_t i = c * kChunk; i < std::min(count, (c + 1) * kChunk); ++i)
                if (kept(i)) index[i] = next++;
        });
        return offset[chunks];
    }

    IndexedMesh& mesh_;
    const FieldProgram& field_;
    SimplifyOptions options_;
    VertexFans facesOf_;
    std::unique_ptr<Quadric[]> quadric_;
    std::vector<uint32_t> stamp_;
    // Bytes, not std::vector<bool>: blocks write their own vertices' flags
    // concurrently.
    std::vector<uint8_t> removedVertex_, removedFace_;
    std::vector<uint8_t> deferred_;  ///< an edge here waits for the whole-mesh queue
    std::vector<uint32_t> block_;    ///< the block owning each vertex
    std::vector<uint8_t> interior_;  ///< all faces around the vertex lie in its block
    std::vector<double> aspect_;     ///< each face's aspect ratio, kept current
    // Marks for neighbour sets, written by the worker owning the vertex;
    // cleared between rounds, whose workers own other vertices.
    mutable std::vector<uint32_t> mark_;
};

}  // namespace

size_t simplifyMesh(IndexedMesh& mesh, const FieldProgram& field, const SimplifyOptions& options) {
    if (mesh.triangles.empty()) return 0;
    return Simplifier(mesh, field, options).run();
}

}  // namespace isotrace::geometry
