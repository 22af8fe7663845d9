// Blob sums with polynomial kernels traced through exact polynomial roots
// must agree with the general sphere tracer on every ray: a random cluster
// of (1 - a^2)^3 blobs (with some negative ones carving it) and Wyvill's
// soft objects under a transform, and Blender's metaball elements (segment,
// rectangle and box cores in skewed frames) among round blobs.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include <memory>
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

// Every other blob gets a core (a segment, rectangle or box, or none: an
// ellipsoid) in a random frame, scaled and sheared.
BlobbyField shapedCluster(int count, uint32_t seed) {
    BlobbyField f = cluster(BlobKernel::Poly6, count, seed);
    std::mt19937 rng(seed + 1);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto shapes = std::make_shared<std::vector<BlobShape>>();
    for (size_t i = 0; i < f.blobs.size(); i += 2) {
        BlobShape shape;
        const int kind = int(i / 2 % 4);
        shape.halfSize = Vec3(kind >= 1 ? 0.6 : 0.0, kind >= 2 ? 0.4 : 0.0, kind >= 3 ? 0.3 : 0.0);
        Mat3 toWorld = Eigen::AngleAxisd(3.0 * u(rng), Vec3(u(rng), u(rng), 1.0).normalized()).toRotationMatrix();
        toWorld *= Vec3(1.0 + 0.5 * u(rng), 1.0 + 0.5 * u(rng), 1.0 + 0.5 * u(rng)).asDiagonal();
        toWorld(0, 1) += 0.3 * u(rng);
        shape.toLocal = toWorld.inverse();
        shape.stretch = Eigen::JacobiSVD<Mat3>(shape.toLocal).singularValues()(0);
        f.blobs[i].shape = uint32_t(shapes->size());
        shapes->push_back(shape);
    }
    f.shapes = std::move(shapes);
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

TEST(BlobCells, ShapedBlobsAgreeWithMarching) {
    FieldProgram program;
    program.addLeaf(shapedCluster(80, 11));
    isotrace::testing::expectSameHitsAsMarching(program, 1500, 200, 40);
}
