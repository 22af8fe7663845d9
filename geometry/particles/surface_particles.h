// Particles spread evenly over the surface of any bounded field, after
// Witkin and Heckbert, "Using Particles to Sample and Control Implicit
// Surfaces" (SIGGRAPH 1994): particles repel their neighbours with Gaussian
// energies of adaptive radius, their motion is projected onto the surface
// (the field stays zero along it), and they split where the surface is
// sparsely covered and die where it is crowded, until the surface is
// sampled at the density asked for, whatever its shape or topology.
//
// Particles start from the project's own surface search: the components of
// a marching-cubes polygonization (each gets particles by its area), plus
// the octree cells of the surface that hold a sign change but no mesh
// vertex (islands and walls thinner than a marching-cubes cell), so every
// component is sampled. The result depends on the seed only, not on the
// number of threads: each step computes every particle from the previous
// step's positions, and splits and deaths run in index order.
#pragma once

#include <cstdint>
#include <vector>

#include "geometry/field_program.h"

namespace isotrace::geometry {

struct ParticleOptions {
    /// The density: about `count` particles in all, or neighbours `spacing`
    /// apart (give one of the two, > 0).
    size_t count = 0;
    double spacing = 0.0;
    uint64_t seed = 1;
    int threads = 0;  ///< 0: all cores
    int iterations = 60;
};

struct SurfaceParticle {
    Vec3 position;
    Vec3 normal;         ///< unit outward normal (the field's gradient)
    double radius = 0;   ///< half the local spacing (the particle's repulsion radius)
    uint32_t component = 0;
};

struct ParticleSampling {
    std::vector<SurfaceParticle> particles;
    double area = 0.0;     ///< the surface's area (of its polygonization)
    double spacing = 0.0;  ///< the neighbour distance aimed at
    /// Particles per connected component of the surface, largest component first.
    std::vector<size_t> componentCounts;
    size_t fissions = 0, deaths = 0;
    int iterations = 0;
};

/// Throws std::invalid_argument (a message for users) for an unbounded
/// field, a field with no surface inside its bounds, or bad options (no
/// density, both count and spacing, a density of more than 10 million).
ParticleSampling spreadParticles(const FieldProgram& field, const ParticleOptions& options);

/// The dynamics alone, from given starting points (near the surface) and a
/// spacing: particles move, split and die until the density is the
/// spacing's, whatever they started from. spreadParticles() calls it after
/// seeding.
ParticleSampling relaxParticles(const FieldProgram& field, std::vector<Vec3> start, double spacing,
                                const ParticleOptions& options);

struct ParticleStatistics {
    /// First-order distance to the surface, |f| / |grad f|.
    double maxDistance = 0, meanDistance = 0;
    /// Distance of each particle to its nearest neighbour: mean, and
    /// coefficient of variation (standard deviation over mean: evenness).
    double nearestMean = 0, nearestVariation = 0;
};

ParticleStatistics measureParticles(const FieldProgram& field, const std::vector<SurfaceParticle>& particles);

/// The same number of points placed naively: uniformly at random in the
/// field's bounds, pushed onto the surface by Newton steps (the baseline
/// the particles are measured against).
std::vector<SurfaceParticle> naiveSurfacePoints(const FieldProgram& field, size_t count, uint64_t seed);

}  // namespace isotrace::geometry
