#include "geometry/meshing/mesh_refiner.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "geometry/meshing/mesh_analysis.h"

namespace isotrace::geometry {

namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
/// Across an edge of more than two faces, or of two oriented alike: never
/// split (it would leave the others a crack).
constexpr uint32_t kBlocked = kNone - 1;
/// Refinement stops when the faces have grown this many times (from half
/// the grid to the accuracy of the whole one takes about three).
constexpr size_t kMaxGrowth = 16;
/// Faces where the gradient is shorter than this fraction of its median on
/// the surface are not refined.
constexpr double kReliableGradientFraction = 0.1;
/// Neither half of a split edge may be longer than this fraction of it, nor
/// the edges to the opposite vertices longer than kMaxOpposite of it.
constexpr double kMaxHalf = 0.95, kMaxOpposite = 1.25;
/// Twice the least area of a new face, relative to the split edge squared.
constexpr double kLeastArea = 1e-6;
/// What a face beyond the tolerance likely becomes: about four faces (two
/// bisections), counting the neighbours the longest-edge paths split too.
constexpr size_t kLikelyFacesPerFailure = 4;

/// Blocks of the parallel first pass hold about this many faces (up to
/// kMaxBlocksPerAxis^3 of them): enough work per block to hide scheduling,
/// few enough faces on their walls.
constexpr double kFacesPerBlock = 4096.0;
constexpr int kMaxBlocksPerAxis = 4;

/// Face flags (Refiner::flags_).
constexpr char kFrozen = 1, kWithin = 2, kBeyond = 4;

/// No block: a face on the blocks' walls, or the whole mesh's pass.
constexpr uint32_t kNoBlock = std::numeric_limits<uint32_t>::max();

inline uint64_t undirected(uint32_t a, uint32_t b) { return (uint64_t(std::min(a, b)) << 32) | std::max(a, b); }

class Refiner {
    // A point with the field's value and gradient there: a split point is
    // judged, and its vertex's normal taken, from the evaluation that found it.
    struct SurfaceSample {
        Vec3 position = Vec3::Zero();
        double value = 0.0;
        Vec3 gradient = Vec3::Zero();
    };

    using Face = std::array<uint32_t, 3>;

    // Where splits happen: the whole mesh (one thread), or one block of the
    // parallel first pass, which splits only faces whose vertices all lie in
    // it and writes the faces and vertices it makes into its own slots of
    // the mesh's arrays (closed up when the blocks are done). No two blocks
    // write the same face: a face's vertices never leave their block, and
    // an edge whose ends lie in a block belongs to faces no other block owns.
    struct Region {
        uint32_t block = kNoBlock;  ///< kNoBlock: the whole mesh, appending
        size_t firstFace = 0, faceSlots = 0, faces = 0;           ///< a block's slots, and how many it used
        size_t firstVertex = 0, vertexSlots = 0, vertices = 0;
        std::vector<uint32_t> pending, path;
        /// Faces whose refinement reaches outside the block (or past its
        /// slots): the whole-mesh pass takes them on.
        std::vector<uint32_t> deferred;
        RefineStatistics statistics;
    };

public:
    Refiner(IndexedMesh& mesh, const FieldProgram& field, const RefineOptions& options)
        : mesh_(mesh), field_(field), options_(options),
          arena_(options.threads > 0 ? options.threads : tbb::task_arena::automatic) {
        arena_.execute([&] { findNeighbours(); });
    }

    RefineStatistics run() {
        // The first check of every face in parallel: most pass.
        const size_t n = mesh_.triangles.size();
        leastReliableGradient_ = leastReliableGradient();
        for (size_t t = 0; t < n; ++t) longestInput_ = std::max(longestInput_, longestLength2(uint32_t(t)));
        longestInput_ = std::sqrt(longestInput_);
        for (const Vec3& p : mesh_.vertices) inputBox_.extend(p);
        flags_.assign(n, 0);
        std::vector<char> fails(n, 0);
        arena_.execute([&] { tbb::parallel_for(size_t(0), n, [&](size_t t) { fails[t] = worthRefining(uint32_t(t)); }); });
        // Splits add their faces back to `pending`, to be checked again.
        maxFaces_ = kMaxGrowth * std::max<size_t>(n, 1);
        std::vector<uint32_t> failing;
        for (size_t t = n; t-- > 0;)
            if (fails[t]) failing.push_back(uint32_t(t));
        const int perAxis =
            std::clamp(int(std::lround(std::cbrt(double(n) / kFacesPerBlock))), 1, kMaxBlocksPerAxis);
        if (perAxis > 1) failing = refineBlocks(perAxis, failing);
        whole_.pending = std::move(failing);
        reserveFor(whole_.pending.size());
        drain(whole_);
        RefineStatistics s = whole_.statistics;
        // Faces measured since they last changed need no new measurement.
        std::vector<char> left(mesh_.triangles.size(), 0);
        arena_.execute([&] {
            tbb::parallel_for(size_t(0), left.size(), [&](size_t t) {
                const char f = flags_[t];
                left[t] = (f & kWithin) ? 0 : (f & kBeyond) ? 1 : beyond(uint32_t(t));
            });
        });
        s.facesBeyond = size_t(std::count(left.begin(), left.end(), 1));
        return s;
    }

private:
    // The parallel first pass: the input's box cut into perAxis^3 blocks,
    // each refining its own failing faces at once into slots of room for
    // the faces they will likely become; then the slots are closed up, in
    // block order (so the mesh does not depend on the threads' timing).
    // Returns what the whole-mesh pass must still check: faces on the
    // blocks' walls, and those whose longest-edge path left their block.
    std::vector<uint32_t> refineBlocks(int perAxis, const std::vector<uint32_t>& failing) {
        const size_t n = mesh_.triangles.size(), vertexCount = mesh_.vertices.size();
        const Vec3 cellsPerUnit = (double(perAxis) / inputBox_.extent().array().max(1e-300)).matrix();
        std::vector<uint32_t> vertexBlock(vertexCount);
        faceBlock_.resize(n);
        arena_.execute([&] {
            tbb::parallel_for(size_t(0), vertexCount, [&](size_t v) {
                int cell[3];
                for (int k = 0; k < 3; ++k)
                    cell[k] = std::clamp(int((mesh_.vertices[v][k] - inputBox_.lower[k]) * cellsPerUnit[k]), 0, perAxis - 1);
                vertexBlock[v] = uint32_t((cell[0] * perAxis + cell[1]) * perAxis + cell[2]);
            });
            tbb::parallel_for(size_t(0), n, [&](size_t t) {
                const Face& v = mesh_.triangles[t];
                const uint32_t b = vertexBlock[v[0]];
                faceBlock_[t] = vertexBlock[v[1]] == b && vertexBlock[v[2]] == b ? b : kNoBlock;
            });
        });
        std::vector<Region> regions(size_t(perAxis) * perAxis * perAxis);
        std::vector<size_t> owned(regions.size(), 0);
        for (size_t t = 0; t < n; ++t)
            if (faceBlock_[t] != kNoBlock) ++owned[faceBlock_[t]];
        std::vector<uint32_t> walls;  // failing faces no block owns
        for (uint32_t t : failing) (faceBlock_[t] == kNoBlock ? walls : regions[faceBlock_[t]].pending).push_back(t);
        // Slots: about four faces per failing one (two splits, counting the
        // neighbours split with it), a vertex per two faces (a split of an
        // inner edge makes two faces and one vertex, of an outer one one of
        // each: the budget stops at whichever fills first).
        size_t faces = n, vertices = vertexCount;
        for (size_t b = 0; b < regions.size(); ++b) {
            Region& r = regions[b];
            r.block = uint32_t(b);
            r.faceSlots = std::min((kMaxGrowth - 1) * owned[b], kLikelyFacesPerFailure * r.pending.size());
            r.vertexSlots = r.faceSlots / 2 + 1;
            r.firstFace = faces;
            r.firstVertex = vertices;
            faces += r.faceSlots;
            vertices += r.vertexSlots;
        }
        resizeMesh(faces, vertices);
        arena_.execute([&] {
            tbb::parallel_for(size_t(0), regions.size(), [&](size_t b) {
                Region& r = regions[b];
                drain(r);
                r.deferred.insert(r.deferred.end(), r.pending.begin(), r.pending.end());  // left by the budget
            });
        });
        // Close up the slots: each block's faces and vertices move down to
        // follow the previous block's, and every reference to them moves
        // with them.
        std::vector<size_t> faceStarts, faceShifts, vertexStarts, vertexShifts;
        faces = n;
        vertices = vertexCount;
        for (const Region& r : regions) {
            faceStarts.push_back(r.firstFace);
            faceShifts.push_back(r.firstFace - faces);
            vertexStarts.push_back(r.firstVertex);
            vertexShifts.push_back(r.firstVertex - vertices);
            std::copy_n(mesh_.triangles.begin() + r.firstFace, r.faces, mesh_.triangles.begin() + faces);
            std::copy_n(neighbours_.begin() + r.firstFace, r.faces, neighbours_.begin() + faces);
            std::copy_n(flags_.begin() + r.firstFace, r.faces, flags_.begin() + faces);
            std::copy_n(mesh_.vertices.begin() + r.firstVertex, r.vertices, mesh_.vertices.begin() + vertices);
            if (!mesh_.normals.empty())
                std::copy_n(mesh_.normals.begin() + r.firstVertex, r.vertices, mesh_.normals.begin() + vertices);
            faces += r.faces;
            vertices += r.vertices;
            whole_.statistics.splits += r.statistics.splits;
            whole_.statistics.refusedSplits += r.statistics.refusedSplits;
        }
        resizeMesh(faces, vertices);
        auto moved = [](uint32_t id, size_t first, const std::vector<size_t>& starts, const std::vector<size_t>& shifts) {
            if (id < first || id >= kBlocked) return id;
            const size_t b = size_t(std::upper_bound(starts.begin(), starts.end(), size_t(id)) - starts.begin()) - 1;
            return uint32_t(id - shifts[b]);
        };
        arena_.execute([&] {
            tbb::parallel_for(size_t(0), faces, [&](size_t t) {
                for (uint32_t& v : mesh_.triangles[t]) v = moved(v, vertexCount, vertexStarts, vertexShifts);
                for (uint32_t& f : neighbours_[t]) f = moved(f, n, faceStarts, faceShifts);
            });
        });
        std::vector<uint32_t> pending;
        for (const Region& r : regions)
            for (uint32_t t : r.deferred) pending.push_back(moved(t, n, faceStarts, faceShifts));
        faceBlock_.clear();
        // Walls first, in the order the whole-mesh pass pops them.
        pending.insert(pending.end(), walls.begin(), walls.end());
        return pending;
    }

    void resizeMesh(size_t faces, size_t vertices) {
        mesh_.triangles.resize(faces);
        neighbours_.resize(faces);
        flags_.resize(faces);
        mesh_.vertices.resize(vertices);
        if (!mesh_.normals.empty()) mesh_.normals.resize(vertices);
    }

    void drain(Region& r) {
        while (!r.pending.empty() && withinBudget(r)) {
            const uint32_t t = r.pending.back();
            r.pending.pop_back();
            if (!(flags_[t] & kFrozen) && worthRefining(t) &&
                longestLength2(t) >= options_.minEdgeLength * options_.minEdgeLength)
                refine(r, t);
        }
    }

    bool withinBudget(const Region& r) const {
        return r.block == kNoBlock ? mesh_.triangles.size() < maxFaces_
                                   : r.faces + 2 <= r.faceSlots && r.vertices + 1 <= r.vertexSlots;
    }

    // Room for the faces the failing ones will likely become (each about
    // four), so that the arrays grow without copying: on the sphere of
    // bench/polygonize_throughput, refinement took 0.124 s growing them by
    // doubling and 0.114 s with room made first.
    void reserveFor(size_t failing) {
        const size_t n = mesh_.triangles.size();
        const size_t faces = std::max(n, std::min(maxFaces_, n + kLikelyFacesPerFailure * failing));
        const size_t vertices = mesh_.vertices.size() + faces - n;  // a split adds one vertex, two faces or one
        mesh_.triangles.reserve(faces);
        neighbours_.reserve(faces);
        flags_.reserve(faces);
        mesh_.vertices.reserve(vertices);
        if (!mesh_.normals.empty()) mesh_.normals.reserve(vertices);
        whole_.pending.reserve(2 * (faces - n) + failing);  // a split queues its faces again
    }

    // Whether region r may split face t: all of it (the whole mesh), or
    // the faces of its block, old or new (a block's path never reaches
    // another block's new faces: they share no edge with its own).
    bool owns(const Region& r, uint32_t t) const {
        return r.block == kNoBlock || t >= faceBlock_.size() || faceBlock_[t] == r.block;
    }

    // neighbours_[t][k]: the face across edge k of t (from vertex k to k + 1),
    // kNone on a boundary, kBlocked on a non-manifold or misoriented edge.
    // Through the faces around each vertex (counted, then filled: no sort):
    // an edge's other faces are among those around its first vertex.
    void findNeighbours() {
        const size_t n = mesh_.triangles.size();
        std::vector<uint32_t> start(mesh_.vertices.size() + 1, 0);
        for (const auto& t : mesh_.triangles)
            for (uint32_t v : t) ++start[v + 1];
        for (size_t v = 0; v + 1 < start.size(); ++v) start[v + 1] += start[v];
        std::vector<uint32_t> around(start.back()), next(start.begin(), start.end() - 1);
        for (uint32_t f = 0; f < n; ++f)
            for (uint32_t v : mesh_.triangles[f]) around[next[v]++] = f;
        neighbours_.resize(n);
        tbb::parallel_for(size_t(0), n, [&](size_t t) {
            const auto& v = mesh_.triangles[t];
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = v[k], b = v[(k + 1) % 3];
                // The one other face running b to a is the neighbour; more
                // faces on the edge, or one running a to b too, block it.
                uint32_t neighbour = kNone;
                int others = 0;
                for (uint32_t i = start[a]; i < start[a + 1]; ++i) {
                    const uint32_t f = around[i];
                    if (f == t) continue;
                    const auto& w = mesh_.triangles[f];
                    for (int j = 0; j < 3; ++j) {
                        if (w[j] == b && w[(j + 1) % 3] == a) ++others, neighbour = f;
                        else if (w[j] == a && w[(j + 1) % 3] == b) others += 2;
                    }
                }
                neighbours_[t][k] = others == 0 ? kNone : others == 1 ? neighbour : kBlocked;
            }
        });
    }

    double distance(const Vec3& p, double* gradientNorm = nullptr) const {
        return surfaceDistance(field_, p, gradientNorm);
    }

    Vec3 centroid(uint32_t t) const {
        const Face& v = mesh_.triangles[t];
        return (mesh_.vertices[v[0]] + mesh_.vertices[v[1]] + mesh_.vertices[v[2]]) / 3.0;
    }

    bool beyond(uint32_t t) const { return distance(centroid(t)) > options_.maxDistance; }

    // Beyond the tolerance, and where |f| / |grad f| measures distance: not
    // where the gradient has fallen far below its typical length on the
    // surface (near a singular point of the field, such as the saddle of a
    // smooth union, smaller faces only come nearer the point and look
    // farther).
    // The measurement is kept in the face's flags (each face is measured by
    // the one thread that owns it).
    bool worthRefining(uint32_t t) {
        double gradientNorm;
        const bool far = distance(centroid(t), &gradientNorm) > options_.maxDistance;
        const bool worth = far && gradientNorm >= leastReliableGradient_;
        flags_[t] = char((flags_[t] & kFrozen) | (far ? kBeyond : kWithin));
        return worth;
    }

    // A tenth of the median gradient length at (up to 4,096 of) the vertices.
    double leastReliableGradient() const {
        const size_t n = mesh_.vertices.size(), stride = std::max<size_t>(1, n / 4096);
        std::vector<double> lengths;
        for (size_t v = 0; v < n; v += stride) {
            Vec3 g;
            field_.valueAndGradient(mesh_.vertices[v], g);
            lengths.push_back(g.norm());
        }
        if (lengths.empty()) return 0.0;
        std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
        return kReliableGradientFraction * lengths[lengths.size() / 2];
    }

    double length2(uint32_t a, uint32_t b) const { return (mesh_.vertices[a] - mesh_.vertices[b]).squaredNorm(); }

    // The longest edge, ties broken by the edge's vertex numbers so that the
    // two faces of an edge agree.
    int longest(uint32_t t) const {
        const Face& v = mesh_.triangles[t];
        int best = 0;
        double bestLength = length2(v[0], v[1]);
        uint64_t bestKey = undirected(v[0], v[1]);
        for (int k = 1; k < 3; ++k) {
            const double l = length2(v[k], v[(k + 1) % 3]);
            const uint64_t key = undirected(v[k], v[(k + 1) % 3]);
            if (l > bestLength || (l == bestLength && key > bestKey)) {
                best = k;
                bestLength = l;
                bestKey = key;
            }
        }
        return best;
    }

    double longestLength2(uint32_t t) const {
        const Face& v = mesh_.triangles[t];
        const int k = longest(t);
        return length2(v[k], v[(k + 1) % 3]);
    }

    // Rivara's longest-edge propagation path: split t's longest edge once it
    // is also the longest of the face beyond it, splitting that face first
    // when it is not (its longest edge is longer, so the path ends). Where
    // Newton cannot bring the new vertex within the tolerance, the field is
    // not smooth there (or its gradient nearly vanishes, and |f| / |grad f|
    // is no distance): the edge stays whole, its faces are not refined
    // again, and the path is given up (the splits made along it are
    // complete in themselves). A block gives up a path that reaches a face
    // it does not own, and leaves t to the whole-mesh pass.
    void refine(Region& r, uint32_t t) {
        r.path.clear();
        r.path.push_back(t);
        while (!r.path.empty()) {
            if (!withinBudget(r)) {
                if (r.block != kNoBlock) r.deferred.push_back(t);
                return;
            }
            const uint32_t s = r.path.back();
            if (flags_[s] & kFrozen) return;
            const int k = longest(s);
            const uint32_t u = neighbours_[s][k];
            if (u == kBlocked) return;  // t stays as it is
            if (u != kNone && !owns(r, u)) {
                r.deferred.push_back(t);
                return;
            }
            if (u == kNone || neighbours_[u][longest(u)] == s) {
                SurfaceSample p;
                if (!splitPoint(s, k, u, p)) {
                    flags_[s] |= kFrozen;
                    if (u != kNone) flags_[u] |= kFrozen;
                    ++r.statistics.refusedSplits;
                    return;
                }
                split(r, s, k, p);
                r.path.pop_back();
            } else {
                r.path.push_back(u);
            }
        }
    }

    // Where to split edge k of t (u the face beyond it): the point of the
    // surface nearest the arc's estimated middle, else nearest the midpoint,
    // by Newton steps along the gradient; or,
    // where that point would not do (near a crease the gradient jumps and
    // Newton may slide sideways), the surface's crossing of the line through
    // the midpoint along the faces' normal; or the midpoint itself, if
    // within the tolerance. False when none does.
    bool splitPoint(uint32_t t, int k, uint32_t u, SurfaceSample& p) const {
        const Face& v = mesh_.triangles[t];
        const Vec3 &a = mesh_.vertices[v[k]], &b = mesh_.vertices[v[(k + 1) % 3]];
        const double length = (a - b).norm();
        const Vec3 midpoint = 0.5 * (a + b);
        const Vec3 arc = arcMidpoint(v[k], v[(k + 1) % 3], midpoint);
        if (nearestByNewton(arc, length, p) && acceptable(t, k, u, keptInBox(p, u))) return true;
        // Far from the arc's estimate (large faces, a crease), from the midpoint.
        if (arc != midpoint && nearestByNewton(midpoint, length, p) && acceptable(t, k, u, keptInBox(p, u)))
            return true;
        Vec3 normal = faceNormal(t), crossing;
        if (u != kNone) normal += faceNormal(u);
        if (normal.norm() > 0 && crossingAlong(midpoint, normal.normalized(), length, crossing) &&
            acceptable(t, k, u, keptInBox(p = sampleAt(crossing), u)))
            return true;
        p = sampleAt(midpoint);
        return acceptable(t, k, u, p);
    }

    // Where Newton starts for the surface point nearest the middle of edge
    // (a, b): the midpoint moved out by the arc's height estimated from the
    // ends' normals, (n_a - n_b)·(a - b) / 8 along their mean (exact to
    // second order: on a sphere of radius r it is |a - b|² / 8r), so that one
    // evaluation usually finds it within the tolerance's thousandth where the
    // chord's midpoint needed two. The midpoint itself where the normals are
    // unknown or far apart.
    Vec3 arcMidpoint(uint32_t a, uint32_t b, const Vec3& midpoint) const {
        if (mesh_.normals.empty()) return midpoint;
        const Vec3 &na = mesh_.normals[a], &nb = mesh_.normals[b];
        if (!(na.dot(nb) > 0.5)) return midpoint;
        const Vec3 mean = (na + nb).normalized();
        return midpoint + ((na - nb).dot(mesh_.vertices[a] - mesh_.vertices[b]) / 8.0) * mean;
    }

    SurfaceSample sampleAt(const Vec3& p) const {
        SurfaceSample s{p};
        s.value = field_.valueAndGradient(p, s.gradient);
        return s;
    }

    // An open surface ends where marching cubes' grid does, on the input's
    // bounding box: a point splitting an edge of the opening (no face u
    // beyond it) is kept on that box.
    const SurfaceSample& keptInBox(SurfaceSample& s, uint32_t u) const {
        if (u != kNone) return s;
        const Vec3 inside = s.position.cwiseMax(inputBox_.lower).cwiseMin(inputBox_.upper);
        if (inside != s.position) s = sampleAt(inside);
        return s;
    }

    Vec3 faceNormal(uint32_t t) const {
        const Face& v = mesh_.triangles[t];
        const Vec3 n = (mesh_.vertices[v[1]] - mesh_.vertices[v[0]]).cross(mesh_.vertices[v[2]] - mesh_.vertices[v[0]]);
        const double l = n.norm();
        return l > 0 ? Vec3(n / l) : Vec3::Zero();
    }

    // Newton steps along the gradient from `start`, each at most half the
    // edge's length; the best point, if within the tolerance.
    bool nearestByNewton(const Vec3& start, double length, SurfaceSample& best) const {
        Vec3 p = start;
        double bestDistance = std::numeric_limits<double>::infinity();
        for (int i = 0; i < 8; ++i) {
            Vec3 g;
            const double f = field_.valueAndGradient(p, g);
            const double g2 = g.squaredNorm();
            if (!(g2 > 0) || !std::isfinite(f)) break;
            const double d = std::abs(f) / std::sqrt(g2);
            if (d < bestDistance) {
                bestDistance = d;
                best = {p, f, g};
            }
            if (d <= 1e-3 * options_.maxDistance) break;
            Vec3 step = (f / g2) * g;
            const double stepLength = step.norm();
            if (stepLength > 0.5 * length) step *= 0.5 * length / stepLength;
            p -= step;
        }
        return bestDistance <= options_.maxDistance;
    }

    // The zero of f on the segment start +- reach/2 along `direction`
    // nearest `start` (looked for at an eighth, a quarter and a half of
    // the reach each way), by bisection; false when f keeps its sign.
    bool crossingAlong(const Vec3& start, const Vec3& direction, double length, Vec3& out) const {
        const double f0 = field_.value(start);
        if (f0 == 0) {
            out = start;
            return true;
        }
        for (double reach : {0.125 * length, 0.25 * length, 0.5 * length})
            for (double side : {1.0, -1.0}) {
                double inside = 0, outside = side * reach;
                if ((field_.value(start + outside * direction) > 0) == (f0 > 0)) continue;
                for (int i = 0; i < 60 && std::abs(outside - inside) > 1e-3 * options_.maxDistance; ++i) {
                    const double mid = 0.5 * (inside + outside);
                    ((field_.value(start + mid * direction) > 0) == (f0 > 0) ? inside : outside) = mid;
                }
                out = start + outside * direction;
                return true;
            }
        return false;
    }

    // A split point must lie within the tolerance; neither half of the
    // split edge may be longer than kMaxHalf of it, nor the edges to the
    // opposite vertices longer than kMaxOpposite of it or than the input's
    // longest edge (on a plane the halves are half of it and those edges at
    // most 0.87 of it; at a crease the point moves off the chord); and no
    // new face may fold over or be degenerate. So each split edge shrinks,
    // no edge grows past the input's, and no face collapses.
    bool acceptable(uint32_t t, int k, uint32_t u, const SurfaceSample& sample) const {
        const Face& v = mesh_.triangles[t];
        const Vec3 &a = mesh_.vertices[v[k]], &b = mesh_.vertices[v[(k + 1) % 3]], &c = mesh_.vertices[v[(k + 2) % 3]];
        const double length = (a - b).norm();
        const Vec3& p = sample.position;
        const Vec3& outward = sample.gradient;  // for the orientation test below
        const double f = sample.value, g = outward.norm();
        if (!((g > 0 ? std::abs(f) / g : std::abs(f)) <= options_.maxDistance)) return false;
        if ((p - a).norm() > kMaxHalf * length || (p - b).norm() > kMaxHalf * length) return false;
        const double reach = std::min(kMaxOpposite * length, longestInput_);
        // Each new face not degenerate, and facing the way its parent does,
        // or the way the surface does at the new vertex or at the face's
        // centre (outward, as marching cubes orients them; at a crease or
        // on large faces these differ). Where the two faces of the edge
        // already fold onto each other (a fin marching cubes' feature
        // vertices can leave at a crease), only degenerate halves are
        // refused.
        const bool fin = u != kNone && faceNormal(t).dot(faceNormal(u)) < 0;
        auto halvesKept = [&](const Vec3& x, const Vec3& y, const Vec3& z) {
            if ((p - z).norm() > reach) return false;
            const Vec3 parent = (y - x).cross(z - x);
            for (const auto& [half, centre] : {std::pair{Vec3((p - x).cross(z - x)), Vec3((p + x + z) / 3.0)},
                                               std::pair{Vec3((y - p).cross(z - p)), Vec3((y + p + z) / 3.0)}}) {
                if (!(half.norm() > kLeastArea * length * length)) return false;
                if (fin || half.dot(parent) > 0 || half.dot(outward) > 0) continue;
                Vec3 there;
                field_.valueAndGradient(centre, there);
                if (!(half.dot(there) > 0)) return false;
            }
            return true;
        };
        if (!halvesKept(a, b, c)) return false;
        if (u == kNone) return true;
        const Face& w = mesh_.triangles[u];
        int j = 0;
        while (w[j] != v[(k + 1) % 3]) ++j;
        return halvesKept(b, a, mesh_.vertices[w[(j + 2) % 3]]);
    }

    uint32_t addVertex(Region& r, const SurfaceSample& p) {
        const Vec3 normal = vertexNormal(p.gradient);
        if (r.block == kNoBlock) {
            mesh_.vertices.push_back(p.position);
            if (!mesh_.normals.empty()) mesh_.normals.push_back(normal);
            return uint32_t(mesh_.vertices.size() - 1);
        }
        const size_t m = r.firstVertex + r.vertices++;
        mesh_.vertices[m] = p.position;
        if (!mesh_.normals.empty()) mesh_.normals[m] = normal;
        return uint32_t(m);
    }

    uint32_t addFace(Region& r, const Face& v, const Face& n) {
        if (r.block == kNoBlock) {
            mesh_.triangles.push_back(v);
            neighbours_.push_back(n);
            flags_.push_back(0);
            return uint32_t(mesh_.triangles.size() - 1);
        }
        const size_t f = r.firstFace + r.faces++;
        mesh_.triangles[f] = v;
        neighbours_[f] = n;
        flags_[f] = 0;
        return uint32_t(f);
    }

    // Points the neighbour of face f across edge (x, y) at g. In a block, f
    // may be a face on its wall that it does not own: only the entry for
    // this edge (whose ends are the block's) is written.
    void relink(uint32_t f, uint32_t x, uint32_t y, uint32_t g) {
        if (f == kNone || f == kBlocked) return;
        const Face& v = mesh_.triangles[f];
        for (int k = 0; k < 3; ++k)
            if (undirected(v[k], v[(k + 1) % 3]) == undirected(x, y)) neighbours_[f][k] = g;
    }

    // Splits edge k of t, (a, b), at a new vertex m at p: t = (a, b, c) becomes
    // (a, m, c) and (m, b, c); the face beyond, u = (b, a, d), becomes
    // (b, m, d) and (m, a, d). Orientation is kept.
    void split(Region& r, uint32_t t, int k, const SurfaceSample& p) {
        const Face tv = mesh_.triangles[t];
        const Face tn = neighbours_[t];
        const uint32_t a = tv[k], b = tv[(k + 1) % 3], c = tv[(k + 2) % 3];
        const uint32_t acrossBC = tn[(k + 1) % 3], acrossCA = tn[(k + 2) % 3];
        const uint32_t u = tn[k];
        const uint32_t m = addVertex(r, p);
        ++r.statistics.splits;
        flags_[t] &= kFrozen;  // changed: measured again when popped
        if (u == kNone) {
            const uint32_t t2 = addFace(r, {m, b, c}, {kNone, acrossBC, t});
            mesh_.triangles[t] = {a, m, c};
            neighbours_[t] = {kNone, t2, acrossCA};
            relink(acrossBC, b, c, t2);
            r.pending.insert(r.pending.end(), {t, t2});
            return;
        }
        const Face uv = mesh_.triangles[u];
        const Face un = neighbours_[u];
        int j = 0;
        while (!(uv[j] == b && uv[(j + 1) % 3] == a)) ++j;
        const uint32_t d = uv[(j + 2) % 3], acrossAD = un[(j + 1) % 3], acrossDB = un[(j + 2) % 3];
        flags_[u] &= kFrozen;
        const uint32_t t2 = addFace(r, {m, b, c}, {u, acrossBC, t});
        const uint32_t u2 = addFace(r, {m, a, d}, {t, acrossAD, u});
        mesh_.triangles[t] = {a, m, c};
        neighbours_[t] = {u2, t2, acrossCA};
        mesh_.triangles[u] = {b, m, d};
        neighbours_[u] = {t2, u2, acrossDB};
        relink(acrossBC, b, c, t2);
        relink(acrossAD, a, d, u2);
        r.pending.insert(r.pending.end(), {t, t2, u, u2});
    }

    IndexedMesh& mesh_;
    const FieldProgram& field_;
    RefineOptions options_;
    tbb::task_arena arena_;  ///< options_.threads workers for every parallel step
    std::vector<Face> neighbours_;
    /// Per face: kFrozen (not to refine further), and what the last
    /// measurement of its centroid's distance found (kWithin or kBeyond),
    /// cleared when the face changes.
    std::vector<char> flags_;
    /// In the parallel pass, the block owning each face of the input (all its
    /// vertices lie in it), or kNoBlock; faces past it are the blocks' new ones.
    std::vector<uint32_t> faceBlock_;
    Region whole_;  ///< the whole mesh: its pending faces and statistics
    double leastReliableGradient_ = 0.0;
    size_t maxFaces_ = 0;
    double longestInput_ = 0.0;
    Box3 inputBox_;
};


}  // namespace

RefineStatistics refineMesh(IndexedMesh& mesh, const FieldProgram& field, const RefineOptions& options) {
    if (mesh.triangles.empty()) return {};
    return Refiner(mesh, field, options).run();
}

}  // namespace isotrace::geometry
