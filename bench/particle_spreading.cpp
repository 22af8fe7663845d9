// Particles (Witkin and Heckbert) spread over the tangle and over hand.off's
// variational fit: the time to place 10,000 on 2 threads (median of three)
// and their evenness against a naive sampler (the same number of random
// points pushed onto the surface by Newton steps).
//
//   particle_spreading [count]
#include <cstdio>
#include <cstdlib>

#include "bench_support.h"
#include "geometry/description/field_parser.h"
#include "geometry/particles/surface_particles.h"
#include "renderer/field_hosting.h"

using namespace isotrace;

int main(int argc, char** argv) {
    const size_t count = argc > 1 ? size_t(std::atol(argv[1])) : 10000;
    const std::string scenes = std::string(ISOTRACE_SOURCE_DIR) + "/scenes";
    const geometry::FieldLibrary library(geometry::Json::parse(R"({
        "tangle": {"type": "polynomial", "preset": "tangle"},
        "hand": {"type": "variational", "mesh": "meshes/hand.off"}})"),
                                         "/fields", scenes + "/bench.json", printingFieldOptions());
    std::printf("%zu particles, 2 threads, 60 steps; times are medians of 3 runs\n", count);
    std::printf("%-8s %9s %8s %10s %12s %12s %10s\n", "field", "seconds", "count", "max dist", "nn cv", "naive cv",
                "fissions");
    for (const char* name : {"tangle", "hand"}) {
        const geometry::FieldProgram field = library.compile(name);  // the hand's fit is cached after its first run
        geometry::ParticleOptions options;
        options.count = count;
        options.threads = 2;
        geometry::ParticleSampling sampling;
        const double seconds = bench::medianSeconds(3, [&] { sampling = geometry::spreadParticles(field, options); });
        const auto s = geometry::measureParticles(field, sampling.particles);
        const auto naive = geometry::measureParticles(field, geometry::naiveSurfacePoints(field, count, 1));
        std::printf("%-8s %9.3f %8zu %10.2g %12.3f %12.3f %10zu\n", name, seconds, sampling.particles.size(),
                    s.maxDistance, s.nearestVariation, naive.nearestVariation, sampling.fissions);
    }
}
