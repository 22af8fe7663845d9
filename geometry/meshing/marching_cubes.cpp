#include "geometry/meshing/marching_cubes.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unordered_map>

namespace isotrace::geometry {

namespace {

constexpr int kBrick = 8;                    // cells per brick side
constexpr uint64_t kFeatureKey = 1ULL << 63;  // keys of feature vertices (never shared)

// ---- the cube's combinatorics ----------------------------------------------
// Corner c sits at offset (c & 1, c >> 1 & 1, c >> 2 & 1).

struct CubeEdge {
    int from, to, axis;
};
struct CubeFace {
    std::array<int, 4> corners;  ///< cyclic around the face
    std::array<int, 4> edges;    ///< edges[k] joins corners[k] and corners[k + 1]
    Vec3 outward;
};

struct CubeTables {
    std::array<CubeEdge, 12> edges;
    std::array<std::array<int, 8>, 8> edgeBetween;
    std::array<CubeFace, 6> faces;

    CubeTables() {
        int n = 0;
        for (auto& row : edgeBetween) row.fill(-1);
        for (int axis = 0; axis < 3; ++axis)
            for (int c = 0; c < 8; ++c)
                if (!((c >> axis) & 1)) {
                    edges[n] = {c, c | (1 << axis), axis};
                    edgeBetween[c][c | (1 << axis)] = edgeBetween[c | (1 << axis)][c] = n;
                    ++n;
                }
        int f = 0;
        for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
                const int u = (axis + 1) % 3, v = (axis + 2) % 3, base = side << axis;
                CubeFace face;
                face.corners = {base, base | (1 << u), base | (1 << u) | (1 << v), base | (1 << v)};
                for (int k = 0; k < 4; ++k) face.edges[k] = edgeBetween[face.corners[k]][face.corners[(k + 1) % 4]];
                face.outward = Vec3::Zero();
                face.outward[axis] = side ? 1.0 : -1.0;
                faces[f++] = face;
            }
    }
    /// Whether two cube edges lie on a common face.
    bool shareFace(int e0, int e1) const {
        for (const CubeFace& f : faces) {
            const bool a = std::find(f.edges.begin(), f.edges.end(), e0) != f.edges.end();
            const bool b = std::find(f.edges.begin(), f.edges.end(), e1) != f.edges.end();
            if (a && b) return true;
        }
        return false;
    }
    static Vec3 cornerOffset(int c) { return Vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1); }
    Vec3 edgeMidpoint(int e) const { return 0.5 * (cornerOffset(edges[e].from) + cornerOffset(edges[e].to)); }
};

const CubeTables& tables() {
    static const CubeTables t;
    return t;
}

// ---- per-brick work ----------------------------------------------------------

struct BrickOutput {
    std::vector<uint64_t> keys;  ///< vertex keys, parallel to positions
    std::vector<Vec3> positions, normals;
    std::vector<std::array<uint32_t, 3>> triangles;  ///< indices into this brick's vertices
    long long cells = 0, evaluations = 0;
};

struct Grid {
    Vec3 origin;
    double h;
    std::array<int, 3> cells;  ///< cells per axis
    Vec3 point(int i, int j, int k) const { return origin + h * Vec3(i, j, k); }
    uint64_t edgeKey(int i, int j, int k, int axis) const {
        const uint64_t nx = uint64_t(cells[0]) + 1, ny = uint64_t(cells[1]) + 1;
        return ((uint64_t(k) * ny + uint64_t(j)) * nx + uint64_t(i)) * 3 + uint64_t(axis);
    }
    /// The inverse of edgeKey: the edge's first grid point (i, j, k) and its axis.
    std::array<int, 4> edgeOfKey(uint64_t key) const {
        const uint64_t nx = uint64_t(cells[0]) + 1, ny = uint64_t(cells[1]) + 1, point = key / 3;
        return {int(point % nx), int((point / nx) % ny), int(point / nx / ny), int(key % 3)};
    }
};

class BrickMesher {
public:
    BrickMesher(const FieldProgram& field, const Grid& grid, const MarchingCubesOptions& options, BrickOutput& out)
        : field_(field), grid_(grid), options_(options), out_(out),
          featureCosine_(std::cos(options.featureAngleDegrees * std::numbers::pi / 180.0)) {}

    void run(const std::array<int, 3>& start, const std::array<int, 3>& size) {
        const int sx = size[0] + 1, sy = size[1] + 1, sz = size[2] + 1;
        std::vector<double> values(size_t(sx) * sy * sz);
        for (int k = 0; k < sz; ++k)
            for (int j = 0; j < sy; ++j)
                for (int i = 0; i < sx; ++i)
                    values[(size_t(k) * sy + j) * sx + i] = field_.value(grid_.point(start[0] + i, start[1] + j, start[2] + k));
        out_.evaluations += values.size();
        for (int k = 0; k < size[2]; ++k)
            for (int j = 0; j < size[1]; ++j)
                for (int i = 0; i < size[0]; ++i) {
                    std::array<double, 8> f;
                    for (int c = 0; c < 8; ++c)
                        f[c] = values[(size_t(k + ((c >> 2) & 1)) * sy + (j + ((c >> 1) & 1))) * sx + (i + (c & 1))];
                    ++out_.cells;
                    meshCell({start[0] + i, start[1] + j, start[2] + k}, f);
                }
    }

private:
    void meshCell(const std::array<int, 3>& cell, const std::array<double, 8>& f) {
        const CubeTables& t = tables();
        int insideMask = 0;
        for (int c = 0; c < 8; ++c)
            if (f[c] < 0) insideMask |= 1 << c;
        if (insideMask == 0 || insideMask == 255) return;
        auto inside = [&](int c) { return (insideMask >> c) & 1; };

        // Segments on each face, oriented so the inside lies on their left
        // when the face is seen from outside the cube.
        std::array<int, 12> next;
        next.fill(-1);
        auto addSegment = [&](const CubeFace& face, int e0, int e1, int referenceCorner) {
            const Vec3 p = t.edgeMidpoint(e0), q = t.edgeMidpoint(e1), r = CubeTables::cornerOffset(referenceCorner);
            const double side = (q - p).cross(r - p).dot(face.outward);
            const bool insideOnLeft = (side > 0) == bool(inside(referenceCorner));
            if (insideOnLeft) next[e0] = e1;
            else next[e1] = e0;
        };
        for (const CubeFace& face : t.faces) {
            std::array<int, 4> crossing;
            int n = 0;
            for (int k = 0; k < 4; ++k)
                if (inside(face.corners[k]) != inside(face.corners[(k + 1) % 4])) crossing[n++] = k;
            if (n == 2) {
                // Any inside corner of the face lies on the inside of the segment.
                int reference = face.corners[0];
                for (int c : face.corners)
                    if (inside(c)) reference = c;
                addSegment(face, face.edges[crossing[0]], face.edges[crossing[1]], reference);
            } else if (n == 4) {
                // Asymptotic decider on the face's bilinear interpolant.
                const double a = f[face.corners[0]], b = f[face.corners[1]], c = f[face.corners[2]], d = f[face.corners[3]];
                const double denominator = a + c - b - d;
                const bool saddleInside = denominator != 0 && (a * c - b * d) / denominator < 0;
                // Cut off each corner of the sign that is not joined through the saddle.
                for (int k = 0; k < 4; ++k) {
                    const int corner = face.corners[k];
                    if (bool(inside(corner)) == saddleInside) continue;
                    addSegment(face, face.edges[(k + 3) % 4], face.edges[k], corner);
                }
            }
        }

        // Chain segments into closed loops and triangulate each.
        std::array<bool, 12> used{};
        for (int start = 0; start < 12; ++start) {
            if (next[start] < 0 || used[start]) continue;
            std::array<uint32_t, 12> loop;
            std::array<int, 12> loopEdges;
            int n = 0;
            for (int e = start; !used[e]; e = next[e]) {
                used[e] = true;
                loopEdges[n] = e;
                loop[n++] = edgeVertex(cell, e);
            }
            emitLoop(cell, loop, loopEdges, n);
        }
    }

    uint32_t edgeVertex(const std::array<int, 3>& cell, int e) {
        const CubeEdge& edge = tables().edges[e];
        const int i = cell[0] + (edge.from & 1), j = cell[1] + ((edge.from >> 1) & 1), k = cell[2] + ((edge.from >> 2) & 1);
        const uint64_t key = grid_.edgeKey(i, j, k, edge.axis);
        const auto found = local_.find(key);
        if (found != local_.end()) return found->second;
        // The edge always runs from the lower to the higher grid point, so
        // neighbouring bricks compute the very same vertex.
        Vec3 a = grid_.point(i, j, k), b = a;
        b[edge.axis] += grid_.h;
        double fa = field_.value(a), fb = field_.value(b);
        double ta = 0, tb = 1;
        int side = 0;
        for (int iteration = 0; iteration < 40 && tb - ta > 1e-7; ++iteration) {
            double tm = (ta * fb - tb * fa) / (fb - fa);
            if (!(tm > ta && tm < tb)) tm = 0.5 * (ta + tb);
            const double fm = field_.value(a + tm * (b - a));
            ++out_.evaluations;
            if (fm == 0) {
                ta = tb = tm;
                break;
            }
            if ((fm < 0) == (fa < 0)) {
                ta = tm;
                fa = fm;
                if (side == 1) fb *= 0.5;
                side = 1;
            } else {
                tb = tm;
                fb = fm;
                if (side == -1) fa *= 0.5;
                side = -1;
            }
        }
        out_.evaluations += 2;
        return addVertex(key, a + 0.5 * (ta + tb) * (b - a));
    }

    uint32_t addVertex(uint64_t key, const Vec3& p) {
        Vec3 g;
        field_.valueAndGradient(p, g);
        ++out_.evaluations;
        const double n = g.norm();
        const uint32_t index = static_cast<uint32_t>(out_.positions.size());
        out_.keys.push_back(key);
        out_.positions.push_back(p);
        out_.normals.push_back(n > 0 ? Vec3(g / n) : Vec3(0, 1, 0));
        if (!(key & kFeatureKey)) local_.emplace(key, index);
        return index;
    }

    void emitLoop(const std::array<int, 3>& cell, const std::array<uint32_t, 12>& loop,
                  const std::array<int, 12>& loopEdges, int n) {
        if (options_.sharpFeatures && n >= 3) {
            if (auto feature = featurePoint(cell, loop, n)) {
                fan(addVertex(kFeatureKey | out_.positions.size(), *feature), loop, n);
                return;
            }
        }
        // Fan from a loop vertex whose diagonals leave every cube face: a
        // diagonal between two vertices of one face would be drawn by the
        // neighbouring cube as well, and its edge would join four triangles.
        for (int apex = 0; apex < n; ++apex) {
            bool clean = true;
            for (int k = 2; k + 1 < n && clean; ++k)
                clean = !tables().shareFace(loopEdges[apex], loopEdges[(apex + k) % n]);
            if (!clean) continue;
            for (int k = 1; k + 1 < n; ++k)
                addTriangle(loop[apex], loop[(apex + k) % n], loop[(apex + k + 1) % n]);
            return;
        }
        // Otherwise fan around a new vertex: the loop's mean, moved onto the surface.
        Vec3 mean = Vec3::Zero();
        for (int k = 0; k < n; ++k) mean += out_.positions[loop[k]];
        mean /= n;
        Vec3 p = mean;
        for (int i = 0; i < 4; ++i) {
            Vec3 g;
            const double f = field_.valueAndGradient(p, g);
            out_.evaluations++;
            if (!(g.squaredNorm() > 0)) break;
            p -= (f / g.squaredNorm()) * g;
        }
        const Vec3 lo = grid_.point(cell[0], cell[1], cell[2]);
        if (!Box3(lo, lo + Vec3::Constant(grid_.h)).contains(p)) p = mean;
        fan(addVertex(kFeatureKey | out_.positions.size(), p), loop, n);
    }

    void fan(uint32_t center, const std::array<uint32_t, 12>& loop, int n) {
        for (int k = 0; k < n; ++k) addTriangle(center, loop[k], loop[(k + 1) % n]);
    }

    void addTriangle(uint32_t a, uint32_t b, uint32_t c) {
        // Loops run with the inside on their left seen from outside the
        // cube, which makes (a, c, b) face outwards.
        out_.triangles.push_back({a, c, b});
    }

    // Kobbelt et al.: where the loop's normals span a wide angle, the
    // surface has an edge or corner in this cell; put a vertex where the
    // tangent planes meet (least squares, small singular values dropped).
    std::optional<Vec3> featurePoint(const std::array<int, 3>& cell, const std::array<uint32_t, 12>& loop, int n) {
        double minCosine = 1.0;
        Vec3 mass = Vec3::Zero();
        for (int a = 0; a < n; ++a) {
            mass += out_.positions[loop[a]];
            for (int b = a + 1; b < n; ++b)
                minCosine = std::min(minCosine, out_.normals[loop[a]].dot(out_.normals[loop[b]]));
        }
        if (minCosine > featureCosine_) return std::nullopt;
        mass /= n;
        Eigen::Matrix<double, 12, 3> A = Eigen::Matrix<double, 12, 3>::Zero();
        Eigen::Matrix<double, 12, 1> rhs = Eigen::Matrix<double, 12, 1>::Zero();
        for (int k = 0; k < n; ++k) {
            A.row(k) = out_.normals[loop[k]].transpose();
            rhs[k] = out_.normals[loop[k]].dot(out_.positions[loop[k]] - mass);
        }
        Eigen::JacobiSVD<Eigen::Matrix<double, 12, 3>> svd(A, Eigen::ComputeFullU | Eigen::ComputeFullV);
        svd.setThreshold(0.1);  // drop directions the normals do not constrain
        const Vec3 x = mass + svd.solve(rhs);
        const Vec3 lo = grid_.point(cell[0], cell[1], cell[2]);
        const Box3 box(lo, lo + Vec3::Constant(grid_.h));
        // A point outside its cell could fold the fan over its neighbours.
        if (!box.contains(x)) return std::nullopt;
        // Where the normals merely turn fast (a smooth, tight bend) the planes
        // meet off the surface: only a real edge or corner keeps its vertex.
        Vec3 g;
        const double f = field_.valueAndGradient(x, g);
        ++out_.evaluations;
        if (std::abs(f) > 0.05 * grid_.h * std::max(g.norm(), 1e-12)) return std::nullopt;
        // Every fan triangle must face along the normals of its loop
        // vertices, or the fan would fold: keep the plain loop then.
        for (int k = 0; k < n; ++k) {
            const Vec3& a = out_.positions[loop[k]];
            const Vec3& b = out_.positions[loop[(k + 1) % n]];
            const Vec3 faceNormal = (b - x).cross(a - x);  // the orientation addTriangle gives (x, b, a)
            if (faceNormal.dot(out_.normals[loop[k]] + out_.normals[loop[(k + 1) % n]]) <= 0) return std::nullopt;
        }
        return x;
    }

    const FieldProgram& field_;
    const Grid& grid_;
    const MarchingCubesOptions& options_;
    BrickOutput& out_;
    double featureCosine_;
    std::unordered_map<uint64_t, uint32_t> local_;
};

struct BrickRange {
    std::array<int, 3> start, size;
};

// Descends an octree over cell ranges, keeping ranges whose value interval
// may contain zero, down to bricks.
void collectBricks(const FieldProgram& field, const Grid& grid, const BrickRange& r, std::vector<BrickRange>& bricks,
                   long long& visited) {
    const Vec3 lo = grid.point(r.start[0], r.start[1], r.start[2]);
    const Vec3 hi = grid.point(r.start[0] + r.size[0], r.start[1] + r.size[1], r.start[2] + r.size[2]);
    ++visited;
    if (!field.range(Box3(lo, hi)).containsZero()) return;
    if (r.size[0] <= kBrick && r.size[1] <= kBrick && r.size[2] <= kBrick) {
        bricks.push_back(r);
        return;
    }
    // Split every axis longer than a brick at a multiple of the brick size.
    std::array<std::array<int, 2>, 3> parts;  // size of the low and high part per axis
    for (int a = 0; a < 3; ++a) {
        if (r.size[a] <= kBrick) {
            parts[a] = {r.size[a], 0};
        } else {
            const int low = ((r.size[a] / 2 + kBrick - 1) / kBrick) * kBrick;
            parts[a] = {low, r.size[a] - low};
        }
    }
    for (int c = 0; c < 8; ++c) {
        BrickRange child;
        bool empty = false;
        for (int a = 0; a < 3; ++a) {
            const int half = (c >> a) & 1;
            child.size[a] = parts[a][half];
            child.start[a] = r.start[a] + (half ? parts[a][0] : 0);
            if (child.size[a] == 0) empty = true;
        }
        if (!empty) collectBricks(field, grid, child, bricks, visited);
    }
}

// Whether a vertex on the grid edge `key` can come from another brick too:
// it can when a cell of another brick touches the edge, i.e. when the edge
// lies in a face of the brick (one of the four parallel to the edge).
bool onBrickFace(uint64_t key, const Grid& grid, const BrickRange& brick) {
    const std::array<int, 4> edge = grid.edgeOfKey(key);  // i, j, k, axis
    for (int o = 0; o < 3; ++o) {
        if (o == edge[3]) continue;
        if (edge[o] <= brick.start[o] || edge[o] >= brick.start[o] + brick.size[o]) return true;
    }
    return false;
}

// Welds the bricks' vertices into one mesh, numbered in brick order (a
// vertex takes the number of its key's first appearance) whatever the
// schedule. Only vertices on brick faces can repeat, so only those go
// through the one serial pass; numbering and copying run in parallel.
// Called inside the caller's task arena.
IndexedMesh weld(const std::vector<BrickOutput>& outputs, const std::vector<BrickRange>& bricks, const Grid& grid) {
    const size_t n = outputs.size();
    // Per brick and vertex: its number in the mesh; until known, kNew (to be
    // numbered) or kRepeat (its key appeared in an earlier brick, which
    // `firstOf` names).
    constexpr uint32_t kNew = UINT32_MAX, kRepeat = UINT32_MAX - 1;
    std::vector<std::vector<uint32_t>> index(n);
    std::vector<std::vector<uint32_t>> facing(n);  ///< vertices on brick faces, in order
    tbb::parallel_for(size_t(0), n, [&](size_t b) {
        const BrickOutput& out = outputs[b];
        index[b].assign(out.positions.size(), kNew);
        for (uint32_t v = 0; v < out.positions.size(); ++v)
            if (!(out.keys[v] & kFeatureKey) && onBrickFace(out.keys[v], grid, bricks[b])) facing[b].push_back(v);
    });
    // The serial part: first appearances of the keys on brick faces.
    struct Appearance {
        uint32_t brick, vertex;
    };
    size_t facingCount = 0;
    for (const auto& f : facing) facingCount += f.size();
    std::unordered_map<uint64_t, Appearance> firstOf;
    firstOf.reserve(facingCount);
    for (uint32_t b = 0; b < n; ++b)
        for (uint32_t v : facing[b])
            if (!firstOf.emplace(outputs[b].keys[v], Appearance{b, v}).second) index[b][v] = kRepeat;
    // Numbers: new vertices of earlier bricks first, each brick's in order.
    std::vector<size_t> vertexStart(n + 1, 0), triangleStart(n + 1, 0);
    tbb::parallel_for(size_t(0), n, [&](size_t b) {
        vertexStart[b + 1] = size_t(std::count(index[b].begin(), index[b].end(), kNew));
        triangleStart[b + 1] = outputs[b].triangles.size();
    });
    for (size_t b = 0; b < n; ++b) vertexStart[b + 1] += vertexStart[b], triangleStart[b + 1] += triangleStart[b];
    IndexedMesh mesh;
    mesh.vertices.resize(vertexStart[n]);
    mesh.normals.resize(vertexStart[n]);
    mesh.triangles.resize(triangleStart[n]);
    tbb::parallel_for(size_t(0), n, [&](size_t b) {
        uint32_t next = uint32_t(vertexStart[b]);
        for (size_t v = 0; v < index[b].size(); ++v) {
            if (index[b][v] != kNew) continue;
            mesh.vertices[next] = outputs[b].positions[v];
            mesh.normals[next] = outputs[b].normals[v];
            index[b][v] = next++;
        }
    });
    // Repeats take their first appearance's number (known now), then the
    // triangles are renumbered.
    tbb::parallel_for(size_t(0), n, [&](size_t b) {
        const BrickOutput& out = outputs[b];
        for (uint32_t v : facing[b]) {
            if (index[b][v] != kRepeat) continue;
            const Appearance first = firstOf.at(out.keys[v]);
            index[b][v] = index[first.brick][first.vertex];
        }
        size_t t = triangleStart[b];
        for (const auto& tri : out.triangles) mesh.triangles[t++] = {index[b][tri[0]], index[b][tri[1]], index[b][tri[2]]};
    });
    return mesh;
}

}  // namespace

IndexedMesh marchingCubes(const FieldProgram& field, const Box3& box, const MarchingCubesOptions& options,
                          MarchingCubesStatistics* statistics) {
    Grid grid;
    grid.h = box.extent().maxCoeff() / std::max(1, options.resolution);
    // A margin of a cell keeps surfaces that touch the box closed. The odd
    // fractions keep grid planes off the flat faces that bounds often share
    // (boxes, caps), where exact zeros at corners would make slivers.
    const Vec3 margin = grid.h * Vec3(1.0 + 0.1372, 1.0 + 0.2591, 1.0 + 0.1813);
    grid.origin = box.lower - margin;
    for (int a = 0; a < 3; ++a) grid.cells[a] = int(std::ceil((box.extent()[a] + 2 * margin[a]) / grid.h - 1e-9));

    std::vector<BrickRange> bricks;
    long long visited = 0;
    collectBricks(field, grid, {{0, 0, 0}, grid.cells}, bricks, visited);

    std::vector<BrickOutput> outputs(bricks.size());
    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(size_t(0), bricks.size(), [&](size_t b) {
            BrickMesher(field, grid, options, outputs[b]).run(bricks[b].start, bricks[b].size);
        });
    });

    MarchingCubesStatistics stats;
    stats.bricksVisited = static_cast<long long>(bricks.size());
    for (const BrickOutput& out : outputs) {
        stats.cellsVisited += out.cells;
        stats.fieldEvaluations += out.evaluations;
    }
    IndexedMesh mesh;
    arena.execute([&] { mesh = weld(outputs, bricks, grid); });
    if (statistics) *statistics = stats;
    return mesh;
}

}  // namespace isotrace::geometry
