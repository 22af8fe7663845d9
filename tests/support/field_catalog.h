// One description of every field type and operator, for property tests that
// must hold for all of them (bound soundness, no false misses).
#pragma once

#include <random>
#include <string>
#include <utility>
#include <vector>

#include "geometry/description/field_parser.h"

namespace isotrace::testing {

struct CatalogEntry {
    std::string name;
    std::string json;  ///< a description; may refer to the catalog's "library" names
};

// Test names print the entry's name, not its bytes.
inline void PrintTo(const CatalogEntry& e, std::ostream* os) { *os << e.name; }

/// Named fields the entries may refer to.
inline const char* kCatalogLibrary = R"({
  "ball": {"type": "sphere", "center": [0.2, 0, 0], "radius": 0.9},
  "cube": {"type": "box", "size": [1.4, 1.2, 1.0]},
  "ring": {"type": "torus", "major": 0.8, "minor": 0.25}
})";

/// A torus (major 0.9, minor 0.3) as an OpenVDB level set of 0.08 voxels.
inline const char* kVdbTorus = ISOTRACE_TEST_DATA_DIR "/torus.vdb";

/// A CSG tree of `leaves` primitives drawn at random (spheres, boxes,
/// rounded boxes, tori, capsules and blob pairs, some turned) under
/// operators drawn at random (unions of two to four, intersections,
/// differences and the smooth forms of all three), around the unit cube:
/// the proofs must hold on large trees of mixed operators, not only on the
/// hand-made ones.
inline std::string randomMixedTree(uint32_t seed, int leaves) {
    using geometry::Json;
    std::mt19937 rng(seed);
    auto uniform = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); };
    auto point = [&](double extent) { return Json::array({uniform(-extent, extent), uniform(-extent, extent), uniform(-extent, extent)}); };
    auto primitive = [&]() -> Json {
        const double size = uniform(0.12, 0.35);
        Json leaf;
        switch (std::uniform_int_distribution<int>(0, 5)(rng)) {
            case 0: leaf = {{"type", "sphere"}, {"center", point(0.8)}, {"radius", size}}; break;
            case 1: leaf = {{"type", "box"}, {"center", point(0.8)}, {"size", point(size) }}; break;
            case 2: leaf = {{"type", "box"}, {"center", point(0.8)}, {"size", {2 * size, 1.5 * size, size}}, {"rounding", 0.3 * size}}; break;
            case 3: leaf = {{"type", "torus"}, {"center", point(0.8)}, {"major", size}, {"minor", 0.3 * size}}; break;
            case 4: leaf = {{"type", "capsule"}, {"from", point(0.8)}, {"to", point(0.8)}, {"radius", 0.4 * size}}; break;
            default: {
                const Json c = point(0.7);
                leaf = {{"type", "blobby"}, {"kernel", "poly6"}, {"threshold", 0.3},
                        {"blobs", {{{"center", c}, {"radius", 2 * size}},
                                   {{"center", {c[0].get<double>() + size, c[1], c[2]}}, {"radius", 2 * size}}}}};
            }
        }
        // Box sizes drawn about zero are made positive.
        if (leaf.contains("size"))
            for (auto& v : leaf["size"]) v = std::abs(v.get<double>()) + 0.1;
        if (uniform(0, 1) < 0.2) {
            const Json axis = {uniform(0.2, 1.0), uniform(-1, 1), uniform(-1, 1)};
            leaf = {{"type", "transform"}, {"rotate", {{"axis", axis}, {"angle", uniform(0, 90)}}}, {"of", leaf}};
        }
        return leaf;
    };
    // What an intersection keeps: a large ball or box about the middle.
    auto trim = [&]() -> Json {
        if (uniform(0, 1) < 0.5) return {{"type", "sphere"}, {"center", point(0.3)}, {"radius", uniform(0.7, 1.0)}};
        return {{"type", "box"}, {"center", point(0.3)}, {"size", {uniform(1.2, 1.8), uniform(1.2, 1.8), uniform(1.2, 1.8)}}};
    };
    auto tree = [&](auto&& self, int count) -> Json {
        if (count == 1) return primitive();
        static const char* kOperators[] = {"union", "union", "union", "intersection", "difference",
                                           "smooth_union", "smooth_intersection", "smooth_difference"};
        const std::string op = kOperators[std::uniform_int_distribution<int>(0, 7)(rng)];
        // Unions take two to four operands; the rest two.
        const int operands = op == "union" ? std::min(count, std::uniform_int_distribution<int>(2, 4)(rng)) : 2;
        Json node = {{"type", op}, {"of", Json::array()}};
        if (op.rfind("smooth_", 0) == 0) node["radius"] = uniform(0.02, 0.15);
        // Intersections and differences take one leaf off the rest, so
        // they trim a part rather than empty it.
        if (op.find("union") == std::string::npos) {
            node["of"].push_back(self(self, count - 1));
            node["of"].push_back(op.find("intersection") != std::string::npos ? trim() : primitive());
            return node;
        }
        int left = count;
        for (int k = 0; k < operands; ++k) {
            const int share = k + 1 == operands ? left : std::max(1, left / (operands - k));
            node["of"].push_back(self(self, share));
            left -= share;
        }
        return node;
    };
    return tree(tree, leaves).dump();
}

inline std::vector<CatalogEntry> fieldCatalog() {
    return {
        {"sphere", R"({"type": "sphere", "center": [0.1, -0.2, 0.3], "radius": 0.8})"},
        {"box", R"({"type": "box", "center": [0, 0.1, 0], "size": [1.2, 0.8, 1.6]})"},
        {"rounded_box", R"({"type": "box", "size": [1.2, 0.8, 1.6], "rounding": 0.2})"},
        {"torus", R"({"type": "torus", "major": 0.9, "minor": 0.3})"},
        {"cylinder", R"({"type": "cylinder", "radius": 0.5, "height": 1.5})"},
        {"cone", R"({"type": "cone", "radius": 0.7, "top_radius": 0.2, "height": 1.2})"},
        {"capsule", R"({"type": "capsule", "from": [-0.6, -0.3, 0], "to": [0.5, 0.4, 0.2], "radius": 0.3})"},
        {"half_space", R"({"type": "intersection", "of": [{"type": "plane", "normal": [1, 2, 0.5], "offset": 0.1}, "ball"]})"},
        {"ellipsoid", R"({"type": "ellipsoid", "radii": [1.0, 0.5, 0.7]})"},
        {"octahedron", R"({"type": "octahedron", "center": [0.1, 0, -0.1], "size": 0.9})"},
        {"quadric", R"({"type": "quadric", "coefficients": [1, 2, 1.5, 0.2, 0, 0.1, 0, 0, 0, -0.8], "domain": [[-1.5, -1.5, -1.5], [1.5, 1.5, 1.5]]})"},
        {"tangle", R"({"type": "polynomial", "preset": "tangle"})"},
        {"heart", R"({"type": "polynomial", "preset": "heart"})"},
        {"pretzel2", R"({"type": "polynomial", "preset": "pretzel2"})"},
        {"blobby_blinn", R"({"type": "blobby", "kernel": "blinn", "threshold": 0.4, "blobs": [
            {"center": [-0.4, 0, 0], "radius": 0.7}, {"center": [0.45, 0.1, 0], "radius": 0.6},
            {"center": [0, 0.5, 0.2], "radius": 0.5, "weight": 0.8}]})"},
        {"blobby_metaball", R"({"type": "blobby", "kernel": "metaball", "threshold": 0.3, "blobs": [
            {"center": [-0.4, 0, 0], "radius": 1.0}, {"center": [0.5, 0.1, 0], "radius": 0.9},
            {"center": [0, -0.3, 0.4], "radius": 0.8, "weight": -0.3}]})"},
        {"blobby_soft", R"({"type": "blobby", "kernel": "soft", "threshold": 0.3, "blobs": [
            {"center": [-0.4, 0, 0], "radius": 1.0}, {"center": [0.5, 0.1, 0], "radius": 0.9}]})"},
        {"blobby_poly6", R"({"type": "blobby", "kernel": "poly6", "threshold": 0.25, "blobs": [
            {"center": [-0.4, 0, 0], "radius": 1.1}, {"center": [0.5, 0.1, 0], "radius": 0.9},
            {"center": [0, 0.4, 0.3], "radius": 0.7, "weight": -0.2}]})"},
        {"blobby_elements", R"({"type": "blobby", "kernel": "poly6", "threshold": 0.3, "blobs": [
            {"center": [-0.5, 0, 0], "radius": 0.7},
            {"center": [0.3, 0.2, 0], "radius": 0.5, "half_size": [0.4, 0, 0], "axes": [[0.8, 0.6, 0], [-0.6, 0.8, 0], [0, 0, 1]]},
            {"center": [0, -0.4, 0.2], "radius": 0.4, "half_size": [0.3, 0.2, 0]},
            {"center": [0.1, 0.1, -0.4], "radius": 0.4, "half_size": [0.2, 0.2, 0.15], "axes": [[1, 0.2, 0], [0, 1, 0.3], [0, 0, 1.2]]},
            {"center": [-0.2, 0.5, 0.1], "radius": 0.5, "axes": [[1.4, 0, 0], [0, 0.7, 0], [0, 0, 1]]},
            {"center": [-0.3, 0.1, 0.4], "radius": 0.4, "weight": -0.5, "half_size": [0.2, 0, 0]}]})"},
        {"distance_polyline", R"({"type": "distance", "points": [[-0.8, 0, 0], [0, 0.5, 0], [0.7, -0.2, 0.3]], "radius": 0.2})"},
        {"distance_circle", R"({"type": "distance", "circle": {"center": [0, 0.1, 0], "normal": [1, 1, 0], "radius": 0.7}, "radius": 0.15})"},
        {"convolution", R"({"type": "convolution", "threshold": 0.5, "segments": [
            {"from": [-0.8, 0, 0], "to": [0.8, 0, 0], "radius": 0.3},
            {"from": [0, -0.7, 0], "to": [0, 0.7, 0.2], "radius": 0.25, "weight": 0.9}]})"},
        {"mpu_ring", R"({"type": "mpu", "sample": "ring", "count": 250})"},
        {"mpu_cube", R"({"type": "mpu", "sample": "cube", "count": 300, "accuracy": 0.01})"},
        // Rays through MPU parts are solved in the leaf's frame: a skewing transform checks the mapping.
        {"mpu_transformed", R"({"type": "transform", "rotate": {"axis": [1, 2, 0], "angle": 35}, "scale": [1.4, 0.7, 1.0],
            "of": {"type": "mpu", "sample": "cube", "count": 300, "accuracy": 0.01}})"},
        {"variational", R"({"type": "variational", "boundary": [[0.8, 0.8, 0.8], [0.8, -0.8, -0.8], [-0.8, 0.8, -0.8], [-0.8, -0.8, 0.8]], "interior": [[0, 0, 0]]})"},
        // Local interpolants blended (what fits past the dense limit use), forced on a small set.
        {"variational_partition", R"({"type": "variational", "sample": "ring", "count": 150, "solver": "partition"})"},
        {"variational_hermite", R"({"type": "variational", "hermite": true, "normals": [[0.7, 0, 0, 1, 0, 0], [-0.7, 0, 0, -1, 0, 0],
            [0, 0.5, 0, 0, 1, 0], [0, -0.5, 0, 0, -1, 0], [0, 0, 0.6, 0, 0, 1], [0, 0, -0.6, 0, 0, -1]]})"},
        {"variational_in_csg", R"({"type": "difference", "of": [{"type": "variational", "normals": [[0.7, 0, 0, 1, 0, 0],
            [-0.7, 0, 0, -1, 0, 0], [0, 0.6, 0, 0, 1, 0], [0, -0.6, 0, 0, -1, 0], [0, 0, 0.6, 0, 0, 1], [0, 0, -0.6, 0, 0, -1]]}, "ring"]})"},
        // A level set isotrace wrote (tests/data/README.md): alone, in CSG with
        // analytic fields, and under a skewing transform.
        {"vdb", std::string(R"({"type": "vdb", "file": ")") + kVdbTorus + R"("})"},
        {"vdb_in_csg", std::string(R"({"type": "difference", "of": [{"type": "vdb", "file": ")") + kVdbTorus + R"("}, "ball"]})"},
        {"vdb_transformed", std::string(R"({"type": "transform", "rotate": {"axis": [1, 0, 1], "angle": 40}, "scale": [1.3, 0.8, 1.0],
            "of": {"type": "vdb", "file": ")") + kVdbTorus + R"(", "grid": "surface"}})"},
        // Sphere sets: hundreds of spheres in one leaf, pruned per cell.
        {"scatter_union", R"({"type": "scatter", "count": 150, "seed": 1, "region": [[-0.8, -0.8, -0.8], [0.8, 0.8, 0.8]],
            "shape": {"type": "sphere", "radius": 0.12}, "scale": [0.5, 1.5]})"},
        {"scatter_smooth_union", R"({"type": "scatter", "count": 80, "seed": 2, "operation": "smooth_union", "radius": 0.1,
            "region": [[-0.7, -0.7, -0.7], [0.7, 0.7, 0.7]], "shape": {"type": "sphere", "radius": 0.12}})"},
        {"scatter_intersection", R"({"type": "scatter", "count": 40, "seed": 3, "operation": "intersection",
            "region": [[-0.3, -0.3, -0.3], [0.3, 0.3, 0.3]], "shape": {"type": "sphere", "radius": 1.0}})"},
        // A foam: a cube less a scatter, smoothly joined to another scatter,
        // all under a turning transform.
        {"scatter_in_csg", R"({"type": "transform", "rotate": {"axis": [1, 1, 0], "angle": 25}, "of": {"type": "smooth_union",
            "radius": 0.05, "of": [{"type": "difference", "of": ["cube", {"type": "scatter", "count": 120, "seed": 4,
            "region": [[-0.7, -0.7, -0.7], [0.7, 0.7, 0.7]], "shape": {"type": "sphere", "radius": 0.15}}]},
            {"type": "scatter", "count": 60, "seed": 5, "operation": "smooth_union", "radius": 0.05,
            "region": [[0.6, -0.4, -0.4], [1.0, 0.4, 0.4]], "shape": {"type": "sphere", "radius": 0.1}}]}})"},
        // Large trees drawn at random with every operator.
        {"random_tree_60", randomMixedTree(7, 60)},
        {"random_tree_120", randomMixedTree(8, 120)},
        {"union", R"({"type": "union", "of": ["ball", "ring"]})"},
        {"intersection", R"({"type": "intersection", "of": ["ball", "cube"]})"},
        {"difference", R"({"type": "difference", "of": ["cube", "ball"]})"},
        {"complement_in_csg", R"({"type": "intersection", "of": ["cube", {"type": "complement", "of": "ring"}]})"},
        {"smooth_union", R"({"type": "smooth_union", "radius": 0.3, "of": ["ball", {"type": "sphere", "center": [-0.9, 0.3, 0], "radius": 0.5}]})"},
        {"smooth_intersection", R"({"type": "smooth_intersection", "radius": 0.2, "of": ["ball", "cube"]})"},
        {"smooth_difference", R"({"type": "smooth_difference", "radius": 0.2, "of": ["cube", "ring"]})"},
        {"offset", R"({"type": "offset", "distance": 0.15, "of": "cube"})"},
        {"transform_uniform", R"({"type": "transform", "translate": [0.2, 0, 0], "rotate": {"axis": [1, 1, 0], "angle": 30}, "scale": 0.7, "of": "ring"})"},
        {"transform_nonuniform", R"({"type": "transform", "rotate": {"axis": [0, 0, 1], "angle": 20}, "scale": [1.5, 0.6, 1.0], "of": "ring"})"},
        {"nested_transform_blend", R"({"type": "transform", "scale": 0.5, "of": {"type": "smooth_union", "radius": 0.4, "of": ["ball", "ring"]}})"},
    };
}

inline geometry::FieldProgram compileCatalogEntry(const CatalogEntry& entry) {
    const geometry::Json library = geometry::Json::parse(kCatalogLibrary);
    geometry::FieldLibrary fields(library, "/fields", "catalog");
    return fields.compileDescription(geometry::Json::parse(entry.json), "/" + entry.name);
}

}  // namespace isotrace::testing
