// Blob sums with polynomial kernels traced through exact polynomial roots
// must agree with the general sphere tracer on every ray: a random cluster
// of (1 - a^2)^3 blobs (with some negative ones carving it) and Wyvill's
// soft objects under a transform.
#include <gtest/gtest.h>

#include <random>

#include "geometry/fields/blobby.h"
#include "support/same_hits.h"
#include "support/turned_placement.h"

using namespace isotrace::geometry;

namespace {

BlobbyField cluster(BlobKernel kernel, int count, uint32_t seed) {
    BlobbyField f;
    f.kernel = kernel;
    f.threshold = 0.5;
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, 2.0);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < count; ++i)
        f.blobs.push_back({Vec3(n(rng), n(rng), n(rng)), 0.8 + u(rng), u(rng) < 0.1 ? -0.5 : 1.0});
    return f;
}

}  // namespace

TEST(BlobCells, Poly6ClusterAgreesWithMarching) {
    FieldProgram program;
    program.addLeaf(cluster(BlobKernel::Poly6, 120, 3));
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 300, 50);
}

TEST(BlobCells, TransformedSoftObjectsAgreeWithMarching) {
    const LeafPlacement placement = isotrace::testing::turnedPlacement(0.6, Vec3(0.3, -0.2, 0.1), 1.0);
    FieldProgram program;
    program.addLeaf(cluster(BlobKernel::SoftObject, 60, 5), placement);
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 150, 30);
}
