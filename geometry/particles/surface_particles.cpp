#include "geometry/particles/surface_particles.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "geometry/meshing/polygonizer.h"
#include "geometry/tracing/implicit_surface.h"

namespace isotrace::geometry {

namespace {

constexpr double kSqrt3 = 1.7320508075688772;

// Cells searched for surface the polygonization missed are split at least
// this deep (8^3 over the bounds) even where the field is a distance bound:
// an island is found by a lattice of points inside its cell.
constexpr int kIslandCellDepth = 3;

// Neighbour queries over points: cells of side h, points sorted by cell.
class PointGrid {
public:
    PointGrid(const std::vector<Vec3>& points, double cellSize) : inverse_(1.0 / cellSize) {
        order_.resize(points.size());
        std::iota(order_.begin(), order_.end(), 0u);
        keys_.resize(points.size());
        for (size_t i = 0; i < points.size(); ++i) keys_[i] = keyOf(cellOf(points[i]));
        std::sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
            return keys_[a] != keys_[b] ? keys_[a] < keys_[b] : a < b;
        });
        for (size_t k = 0; k < order_.size();) {
            size_t end = k;
            while (end < order_.size() && keys_[order_[end]] == keys_[order_[k]]) ++end;
            ranges_.emplace(keys_[order_[k]], std::make_pair(uint32_t(k), uint32_t(end)));
            k = end;
        }
    }

    /// Calls visit(j) for every point j in the 27 cells around p.
    template <class Visit>
    void forNear(const Vec3& p, Visit&& visit) const {
        const Eigen::Vector3i c = cellOf(p);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    const auto it = ranges_.find(keyOf(c + Eigen::Vector3i(dx, dy, dz)));
                    if (it == ranges_.end()) continue;
                    for (uint32_t k = it->second.first; k < it->second.second; ++k) visit(order_[k]);
                }
    }

private:
    Eigen::Vector3i cellOf(const Vec3& p) const {
        return {int(std::floor(p.x() * inverse_)), int(std::floor(p.y() * inverse_)), int(std::floor(p.z() * inverse_))};
    }
    static uint64_t keyOf(const Eigen::Vector3i& c) {
        auto part = [](int v) { return uint64_t(uint32_t(v + (1 << 20)) & 0x1FFFFF); };
        return part(c.x()) | (part(c.y()) << 21) | (part(c.z()) << 42);
    }

    double inverse_;
    std::vector<uint32_t> order_;
    std::vector<uint64_t> keys_;
    std::unordered_map<uint64_t, std::pair<uint32_t, uint32_t>> ranges_;
};

struct UnionFind {
    std::vector<uint32_t> parent;
    explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
    uint32_t find(uint32_t a) {
        while (parent[a] != a) a = parent[a] = parent[parent[a]];
        return a;
    }
    void unite(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
};

// Newton steps onto f = 0 along the gradient, each at most maxStep long.
// True when p ends within `tolerance` of the surface (first order).
bool projectToSurface(const FieldProgram& field, Vec3& p, double tolerance, double maxStep, int iterations) {
    for (int k = 0; k < iterations; ++k) {
        Vec3 g;
        const double v = field.valueAndGradient(p, g);
        const double g2 = g.squaredNorm();
        if (!(g2 > 0) || !std::isfinite(v)) return false;
        if (std::abs(v) <= tolerance * std::sqrt(g2)) return true;
        Vec3 step = (v / g2) * g;
        const double length = step.norm();
        if (length > maxStep) step *= maxStep / length;
        p -= step;
    }
    Vec3 g;
    const double v = field.valueAndGradient(p, g);
    return std::abs(v) <= tolerance * g.norm();
}

// A deterministic number in [0, 1) from a seed and two counters.
double hashUnit(uint64_t seed, uint64_t a, uint64_t b) {
    uint64_t x = seed * 0x9E3779B97F4A7C15ull ^ (a + 0x632BE59BD9B4E019ull) * 0xBF58476D1CE4E5B9ull ^ b * 0x94D049BB133111EBull;
    x ^= x >> 31;
    x *= 0xD6E8FEB86659FD93ull;
    x ^= x >> 32;
    return double(x >> 11) * 0x1.0p-53;
}

struct SurfaceComponents {
    std::vector<std::vector<uint32_t>> triangles;  ///< per component, largest first
    std::vector<double> areas;
    std::vector<Vec3> islands;  ///< surface points found only by the octree cells
};

SurfaceComponents findComponents(const FieldProgram& field, const IndexedMesh& mesh) {
    SurfaceComponents out;
    UnionFind sets(mesh.vertices.size());
    for (const auto& t : mesh.triangles) {
        sets.unite(t[0], t[1]);
        sets.unite(t[1], t[2]);
    }
    std::unordered_map<uint32_t, size_t> componentOf;
    std::vector<std::vector<uint32_t>> triangles;
    std::vector<double> areas;
    for (uint32_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        const uint32_t root = sets.find(t[0]);
        auto [it, added] = componentOf.emplace(root, triangles.size());
        if (added) {
            triangles.emplace_back();
            areas.push_back(0.0);
        }
        triangles[it->second].push_back(i);
        areas[it->second] +=
            0.5 * (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
    }
    std::vector<size_t> order(triangles.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return areas[a] > areas[b]; });
    for (size_t k : order) {
        out.triangles.push_back(std::move(triangles[k]));
        out.areas.push_back(areas[k]);
    }

    // Octree cells that hold a sign change but no mesh vertex: surface the
    // polygonization stepped over.
    ImplicitSurfaceOptions options;
    options.cellAccelerators.clear();
    options.distanceCellDepth = kIslandCellDepth;
    const ImplicitSurface surface(field, options);
    if (surface.cells().empty()) return out;
    // Cells differ in size; the grid's cells are as large as the largest,
    // so the 27 around a cell's centre hold every vertex within one cell of it.
    double cellSize = 0.0;
    for (const SurfaceCell& cell : surface.cells()) cellSize = std::max(cellSize, cell.box.extent().maxCoeff());
    const PointGrid vertices(mesh.vertices, cellSize);
    const int n = 4;
    for (const SurfaceCell& cell : surface.cells()) {
        // A cell next to the mesh belongs to a component the mesh found
        // (marching cubes may leave a corner of a cell without a vertex).
        bool covered = false;
        const Box3 around = cell.box.expanded(0.5 * cell.box.extent().maxCoeff());
        vertices.forNear(cell.box.center(), [&](uint32_t v) { covered = covered || around.contains(mesh.vertices[v]); });
        if (covered) continue;
        // A sign change between neighbours of an n^3 lattice, refined by bisection.
        auto at = [&](int i, int j, int k) {
            return Vec3(cell.box.lower + (cell.box.extent().array() * Eigen::Array3d(i, j, k) / n).matrix());
        };
        bool found = false;
        for (int i = 0; i <= n && !found; ++i)
            for (int j = 0; j <= n && !found; ++j)
                for (int k = 0; k < n && !found; ++k) {
                    Vec3 a = at(i, j, k), b = at(i, j, k + 1);
                    double fa = field.value(a), fb = field.value(b);
                    if ((fa < 0) == (fb < 0)) continue;
                    for (int s = 0; s < 60; ++s) {
                        const Vec3 m = 0.5 * (a + b);
                        const double fm = field.value(m);
                        if ((fm < 0) == (fa < 0)) a = m, fa = fm;
                        else b = m, fb = fm;
                    }
                    out.islands.push_back(0.5 * (a + b));
                    found = true;
                }
    }
    return out;
}

// Witkin and Heckbert's dynamics from given starting points (on or near
// the surface), each labelled with its component.
ParticleSampling relax(const FieldProgram& field, std::vector<Vec3> positions, std::vector<uint32_t> componentOf,
                       size_t componentCount, double spacing, const ParticleOptions& options) {
    ParticleSampling result;
    result.spacing = spacing;
    const double tolerance = 1e-9 * field.bounds().extent().norm();
    const double sigmaHat = 0.5 * spacing;  // six neighbours at d give energy 6 e^-2 = 0.81: the paper's 0.8
    const double desiredEnergy = 6.0 * std::exp(-2.0);
    std::vector<double> sigma(positions.size(), sigmaHat);
    std::vector<Vec3> normals(positions.size(), Vec3::Zero());
    for (Vec3& p : positions) projectToSurface(field, p, tolerance, 0.5 * spacing, 30);

    tbb::task_arena arena(options.threads > 0 ? options.threads : tbb::task_arena::automatic);
    std::vector<Vec3> next;
    std::vector<double> energy, nextSigma;
    for (int iteration = 0; iteration < options.iterations; ++iteration) {
        const size_t n = positions.size();
        next.assign(n, Vec3::Zero());
        energy.assign(n, 0.0);
        nextSigma.assign(n, 0.0);
        const double reach = 3.0 * *std::max_element(sigma.begin(), sigma.end());
        const PointGrid grid(positions, reach);
        // A step settles the particles early on and then only refines.
        const double rate = iteration < options.iterations / 2 ? 0.3 : 0.15;
        arena.execute([&] {
            tbb::parallel_for(size_t(0), n, [&](size_t i) {
                const Vec3& p = positions[i];
                const double si2 = sigma[i] * sigma[i];
                Vec3 repulsion = Vec3::Zero();
                double e = 0.0, dEdSigma = 0.0;
                grid.forNear(p, [&](uint32_t j) {
                    if (j == i) return;
                    const Vec3 r = p - positions[j];
                    const double r2 = r.squaredNorm();
                    if (r2 > reach * reach) return;
                    const double sj2 = sigma[j] * sigma[j];
                    const double ei = std::exp(-r2 / (2 * si2)), ej = std::exp(-r2 / (2 * sj2));
                    // Witkin and Heckbert's repulsion: both particles' energies push.
                    repulsion += r * (ei + (si2 / sj2) * ej);
                    e += ei;
                    dEdSigma += ei * r2 / (si2 * sigma[i]);
                });
                Vec3 g;
                field.valueAndGradient(p, g);
                const Vec3 normal = g.normalized();
                repulsion -= normal.dot(repulsion) * normal;  // stay on the surface: move in its tangent plane
                Vec3 step = rate * repulsion;
                const double length = step.norm();
                if (length > 0.5 * sigma[i]) step *= 0.5 * sigma[i] / length;
                Vec3 q = p + step;
                if (!projectToSurface(field, q, tolerance, 0.5 * spacing, 4)) q = p;
                next[i] = q;
                energy[i] = e;
                // The radius grows where energy is low (sparse) and shrinks
                // where it is high (crowded), 10% at most per step.
                const double change = -(e - desiredEnergy) / (dEdSigma + 10.0 / sigma[i]);
                nextSigma[i] = std::clamp(sigma[i] + std::clamp(change, -0.1 * sigma[i], 0.1 * sigma[i]),
                                          0.5 * sigmaHat, 2.0 * sigmaHat);
            });
        });
        positions.swap(next);
        sigma.swap(nextSigma);

        // Fission and death, in index order, every few steps and not at the
        // end (the last steps only relax).
        if (iteration % 2 != 1 || iteration > options.iterations - 10) continue;
        std::vector<Vec3> kept;
        std::vector<double> keptSigma;
        std::vector<uint32_t> keptComponent;
        for (size_t i = 0; i < positions.size(); ++i) {
            // The paper's criteria: a particle near equilibrium (its radius
            // adapted until its energy is about the desired one) measures the
            // local spacing by its radius. Too large: the surface around it
            // is sparse, it splits. Too small: crowded, it may die (at
            // random, so that a crowd thins out rather than vanishes).
            const bool sparse = sigma[i] > 1.08 * sigmaHat && energy[i] < 1.1 * desiredEnergy;
            const bool crowded = sigma[i] < 0.93 * sigmaHat && energy[i] > 0.9 * desiredEnergy;
            if (crowded && hashUnit(options.seed, i, iteration) < 0.3) {
                ++result.deaths;
                continue;
            }
            kept.push_back(positions[i]);
            keptComponent.push_back(componentOf[i]);
            if (sparse) {
                // Split into two of radius sigma / sqrt 2, apart along a tangent.
                Vec3 g;
                field.valueAndGradient(positions[i], g);
                const Vec3 n = g.normalized();
                Vec3 t = n.unitOrthogonal();
                const double angle = 2 * 3.141592653589793 * hashUnit(options.seed ^ 0x5bd1e995, i, iteration);
                t = std::cos(angle) * t + std::sin(angle) * n.cross(t);
                const double s = sigma[i] / std::sqrt(2.0);
                keptSigma.push_back(s);
                Vec3 q = positions[i] + 0.5 * sigma[i] * t;
                if (projectToSurface(field, q, tolerance, 0.5 * spacing, 8)) {
                    kept.push_back(q);
                    keptSigma.push_back(s);
                    keptComponent.push_back(componentOf[i]);
                    ++result.fissions;
                }
            } else {
                keptSigma.push_back(sigma[i]);
            }
        }
        positions.swap(kept);
        sigma.swap(keptSigma);
        componentOf.swap(keptComponent);
    }

    // Settle every particle on the surface and report per component.
    std::vector<size_t> counts(componentCount, 0);
    for (size_t i = 0; i < positions.size(); ++i) {
        Vec3 p = positions[i];
        if (!projectToSurface(field, p, tolerance, 0.5 * spacing, 50)) continue;
        Vec3 g;
        field.valueAndGradient(p, g);
        result.particles.push_back({p, g.normalized(), sigma[i], componentOf[i]});
        ++counts[componentOf[i]];
    }
    for (size_t c : counts)
        if (c > 0) result.componentCounts.push_back(c);
    result.iterations = options.iterations;
    return result;
}

}  // namespace

ParticleSampling spreadParticles(const FieldProgram& field, const ParticleOptions& options) {
    if (options.count == 0 && !(options.spacing > 0))
        throw std::invalid_argument("give the density: a count of particles (> 0) or a spacing (> 0)");
    if (options.count > 0 && options.spacing > 0) throw std::invalid_argument("give a count or a spacing, not both");
    if (!std::isfinite(options.spacing)) throw std::invalid_argument("the spacing must be a finite number");
    const Box3 bounds = field.bounds();
    if (!bounds.isFinite()) throw std::invalid_argument("the field is unbounded: give it \"bounds\"");
    // Search the surface.
    PolygonizeOptions polygonizeOptions;
    polygonizeOptions.resolution = 128;
    polygonizeOptions.threads = options.threads;
    const Polygonization polygonization = polygonize(field, polygonizeOptions);
    const IndexedMesh& mesh = polygonization.mesh;
    SurfaceComponents components = findComponents(field, mesh);
    double area = 0.0;
    for (double a : components.areas) area += a;
    if (area <= 0 && components.islands.empty()) throw std::invalid_argument("the field has no surface inside its bounds");

    // Density: hexagonal packing puts one particle on (sqrt 3 / 2) d^2.
    double spacing = options.spacing;
    if (options.count > 0) spacing = std::sqrt(2.0 * area / (kSqrt3 * double(options.count)));
    const double wanted = area / (0.5 * kSqrt3 * spacing * spacing);
    if (!(wanted <= 1e7)) throw std::invalid_argument("more than 10 million particles: use a larger spacing or a smaller count");
    const double target = options.count > 0 ? double(options.count) : wanted;

    // Initial particles: per component, its share of the count, placed by
    // dart throwing on its triangles (area-weighted random points kept
    // when no earlier one lies within 0.75 d).
    std::vector<Vec3> positions;
    std::vector<uint32_t> componentOf;
    std::mt19937_64 rng(options.seed);
    std::uniform_real_distribution<double> uniform;
    const size_t componentCount = components.triangles.size();
    for (size_t c = 0; c < componentCount; ++c) {
        const size_t share = std::max<size_t>(1, size_t(std::llround(target * components.areas[c] / area)));
        const std::vector<uint32_t>& triangles = components.triangles[c];
        std::vector<double> cumulative(triangles.size());
        double sum = 0.0;
        for (size_t i = 0; i < triangles.size(); ++i) {
            const auto& t = mesh.triangles[triangles[i]];
            sum += (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]).norm();
            cumulative[i] = sum;
        }
        std::vector<Vec3> candidates(6 * share + 16);
        for (Vec3& p : candidates) {
            const size_t i = std::min(triangles.size() - 1, size_t(std::lower_bound(cumulative.begin(), cumulative.end(),
                                                                                     uniform(rng) * sum) - cumulative.begin()));
            const auto& t = mesh.triangles[triangles[i]];
            double u = uniform(rng), v = uniform(rng);
            if (u + v > 1) u = 1 - u, v = 1 - v;
            p = mesh.vertices[t[0]] + u * (mesh.vertices[t[1]] - mesh.vertices[t[0]]) + v * (mesh.vertices[t[2]] - mesh.vertices[t[0]]);
        }
        std::vector<Vec3> accepted;
        std::vector<bool> used(candidates.size(), false);
        for (double radius = 0.75 * spacing; accepted.size() < share && radius > 1e-3 * spacing; radius *= 0.8) {
            // Accepted points hashed by cells of side `radius`: a candidate
            // need only look at the 27 cells around it.
            std::unordered_map<uint64_t, std::vector<uint32_t>> cells;
            auto cellOf = [&](const Vec3& p) {
                return Eigen::Vector3i(int(std::floor(p.x() / radius)), int(std::floor(p.y() / radius)),
                                       int(std::floor(p.z() / radius)));
            };
            auto keyOf = [](const Eigen::Vector3i& c) {
                auto part = [](int v) { return uint64_t(uint32_t(v + (1 << 20)) & 0x1FFFFF); };
                return part(c.x()) | (part(c.y()) << 21) | (part(c.z()) << 42);
            };
            for (uint32_t a = 0; a < accepted.size(); ++a) cells[keyOf(cellOf(accepted[a]))].push_back(a);
            for (size_t k = 0; k < candidates.size() && accepted.size() < share; ++k) {
                if (used[k]) continue;
                const Eigen::Vector3i c = cellOf(candidates[k]);
                bool free = true;
                for (int dx = -1; dx <= 1 && free; ++dx)
                    for (int dy = -1; dy <= 1 && free; ++dy)
                        for (int dz = -1; dz <= 1 && free; ++dz) {
                            const auto it = cells.find(keyOf(c + Eigen::Vector3i(dx, dy, dz)));
                            if (it == cells.end()) continue;
                            for (uint32_t a : it->second)
                                if ((accepted[a] - candidates[k]).squaredNorm() < radius * radius) {
                                    free = false;
                                    break;
                                }
                        }
                if (!free) continue;
                used[k] = true;
                cells[keyOf(c)].push_back(uint32_t(accepted.size()));
                accepted.push_back(candidates[k]);
            }
        }
        for (const Vec3& p : accepted) {
            positions.push_back(p);
            componentOf.push_back(uint32_t(c));
        }
    }
    // Islands: one particle per cluster of cells the polygonization missed.
    {
        UnionFind clusters(components.islands.size());
        for (size_t i = 0; i < components.islands.size(); ++i)
            for (size_t j = 0; j < i; ++j)
                if ((components.islands[i] - components.islands[j]).norm() < 2 * spacing) clusters.unite(uint32_t(i), uint32_t(j));
        std::unordered_map<uint32_t, uint32_t> clusterComponent;
        for (size_t i = 0; i < components.islands.size(); ++i) {
            auto [it, added] = clusterComponent.emplace(clusters.find(uint32_t(i)), uint32_t(componentCount + clusterComponent.size()));
            if (!added) continue;
            positions.push_back(components.islands[i]);
            componentOf.push_back(it->second);
        }
    }

    ParticleSampling result = relax(field, std::move(positions), std::move(componentOf),
                                    componentCount + components.islands.size(), spacing, options);
    result.area = area;
    return result;
}

ParticleSampling relaxParticles(const FieldProgram& field, std::vector<Vec3> start, double spacing,
                                const ParticleOptions& options) {
    if (!(spacing > 0) || !std::isfinite(spacing)) throw std::invalid_argument("the spacing must be positive");
    if (!field.bounds().isFinite()) throw std::invalid_argument("the field is unbounded: give it \"bounds\"");
    std::vector<uint32_t> components(start.size(), 0);
    return relax(field, std::move(start), std::move(components), 1, spacing, options);
}

ParticleStatistics measureParticles(const FieldProgram& field, const std::vector<SurfaceParticle>& particles) {
    ParticleStatistics s;
    if (particles.empty()) return s;
    std::vector<Vec3> points;
    for (const SurfaceParticle& p : particles) {
        Vec3 g;
        const double d = std::abs(field.valueAndGradient(p.position, g)) / std::max(g.norm(), 1e-300);
        s.maxDistance = std::max(s.maxDistance, d);
        s.meanDistance += d / double(particles.size());
        points.push_back(p.position);
    }
    if (points.size() < 2) return s;
    // Nearest neighbours through a grid sized by the mean spacing on the
    // bounding box's scale, widened until every point finds one.
    Box3 box;
    for (const Vec3& p : points) box.extend(p);
    double cell = std::max(box.extent().maxCoeff(), 1e-12) / std::cbrt(double(points.size()));
    std::vector<double> nearest(points.size(), INFINITY);
    for (int attempt = 0; attempt < 8; ++attempt, cell *= 2) {
        const PointGrid grid(points, cell);
        bool all = true;
        for (size_t i = 0; i < points.size(); ++i) {
            if (std::isfinite(nearest[i]) && nearest[i] <= cell) continue;
            double best = INFINITY;
            grid.forNear(points[i], [&](uint32_t j) {
                if (j != i) best = std::min(best, (points[i] - points[j]).norm());
            });
            if (best <= cell) nearest[i] = best;
            else all = false;
        }
        if (all) break;
    }
    double sum = 0, sum2 = 0;
    size_t n = 0;
    for (double d : nearest)
        if (std::isfinite(d)) {
            sum += d;
            sum2 += d * d;
            ++n;
        }
    s.nearestMean = sum / double(n);
    s.nearestVariation = std::sqrt(std::max(0.0, sum2 / double(n) - s.nearestMean * s.nearestMean)) / s.nearestMean;
    return s;
}

std::vector<SurfaceParticle> naiveSurfacePoints(const FieldProgram& field, size_t count, uint64_t seed) {
    const Box3 bounds = field.bounds();
    if (!bounds.isFinite()) throw std::invalid_argument("the field is unbounded: give it \"bounds\"");
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> uniform;
    std::vector<SurfaceParticle> points;
    const double tolerance = 1e-9 * bounds.extent().norm();
    for (size_t attempts = 0; points.size() < count && attempts < 100 * count; ++attempts) {
        Vec3 p = bounds.lower + (bounds.extent().array() * Eigen::Array3d(uniform(rng), uniform(rng), uniform(rng))).matrix();
        if (!projectToSurface(field, p, tolerance, bounds.extent().norm(), 50) || !bounds.contains(p)) continue;
        Vec3 g;
        field.valueAndGradient(p, g);
        points.push_back({p, g.normalized(), 0.0, 0});
    }
    return points;
}

}  // namespace isotrace::geometry
