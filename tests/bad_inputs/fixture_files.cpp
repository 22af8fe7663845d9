// The valid files every case starts from; each case then breaks one thing.
#include <cmath>
#include <fstream>
#include <sstream>

#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {

const char* completeScene() {
    return R"({
 "camera": {"type": "perspective", "from": [0, 1, 6], "to": [0, 0, 0], "up": [0, 1, 0], "fov": 40,
            "aperture": 0.01, "focus_distance": 6},
 "film": {"width": 8, "height": 6, "spp": 1, "sampler": "sobol",
          "filter": {"type": "gaussian", "radius": 1.5, "sigma": 0.5}},
 "integrator": {"type": "path", "max_depth": 4, "rr_depth": 3},
 "materials": {
  "clay": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]},
  "checks": {"type": "diffuse", "albedo": {"type": "checker", "scale": 1, "colors": [[0.8, 0.8, 0.8], [0.2, 0.2, 0.2]]}},
  "chrome": {"type": "mirror", "reflectance": [0.9, 0.9, 0.9]},
  "lamp": {"type": "emissive", "radiance": [2, 2, 2], "two_sided": false},
  "gold": {"type": "conductor", "metal": "gold", "roughness": 0.2},
  "metal": {"type": "conductor", "eta": [0.2, 0.9, 1.1], "k": [3.9, 2.4, 2.2]},
  "glass": {"type": "dielectric", "ior": 1.5, "roughness": 0, "transmittance": [1, 1, 1], "thin": false},
  "coat": {"type": "plastic", "albedo": {"type": "image", "file": "tiles.png", "scale": 1, "sharpness": 4}, "ior": 1.5,
           "roughness": {"type": "noise", "scale": 2, "octaves": 3, "seed": 1, "colors": [0.1, 0.4]}},
  "ramp": {"type": "diffuse", "albedo": {"type": "field_ramp", "field": "ball", "quantity": "value",
                                         "ramp": [[-1, [0, 0, 0]], [1, [1, 1, 1]]]}}
 },
 "fields": {
  "ball": {"type": "sphere", "center": [0, 0, 0], "radius": 1},
  "block": {"type": "box", "size": [1, 1, 1], "rounding": 0.1},
  "ring": {"type": "torus", "center": [0, 0, 0], "major": 1, "minor": 0.25},
  "tube": {"type": "cylinder", "radius": 0.5, "height": 1},
  "spike": {"type": "cone", "radius": 0.5, "top_radius": 0.1, "height": 1},
  "pill": {"type": "capsule", "from": [0, 0, 0], "to": [0, 1, 0], "radius": 0.2},
  "egg": {"type": "ellipsoid", "radii": [1, 0.5, 0.5]},
  "gem": {"type": "octahedron", "center": [0, 0, 0], "size": 0.8},
  "tangle": {"type": "polynomial", "preset": "tangle"},
  "cubic": {"type": "polynomial", "terms": [[1, 2, 0, 0], [1, 0, 2, 0], [1, 0, 0, 2], [-1, 0, 0, 0]],
            "domain": [[-2, -2, -2], [2, 2, 2]]},
  "round": {"type": "quadric", "coefficients": [1, 1, 1, 0, 0, 0, 0, 0, 0, -1], "domain": [[-2, -2, -2], [2, 2, 2]]},
  "blobs": {"type": "blobby", "kernel": "blinn", "threshold": 0.5, "blobbiness": 4,
            "blobs": [{"center": [0, 0, 0], "radius": 1, "weight": 1}, {"center": [1, 0, 0], "radius": 1}]},
  "stick": {"type": "distance", "radius": 0.2, "points": [[0, 0, 0], [1, 0, 0]]},
  "hoop": {"type": "distance", "radius": 0.1, "circle": {"center": [0, 0, 0], "normal": [0, 1, 0], "radius": 1}},
  "arm": {"type": "convolution", "threshold": 0.5,
          "segments": [{"from": [0, 0, 0], "to": [1, 0, 0], "radius": 0.3, "weight": 1}]},
  "cut": {"type": "difference", "of": ["block", "ball"]},
  "blend": {"type": "smooth_union", "of": ["ball", {"type": "sphere", "radius": 0.5, "center": [1, 0, 0]}],
            "radius": 0.2},
  "grown": {"type": "offset", "of": "pill", "distance": 0.1},
  "moved": {"type": "transform", "of": "ring", "translate": [0, 1, 0], "rotate": {"axis": [0, 1, 0], "angle": 30},
            "scale": 2},
  "half": {"type": "intersection", "of": ["ball", {"type": "plane", "normal": [0, 1, 0], "offset": 0}]},
  "hollow": {"type": "intersection", "of": ["ball", {"type": "complement", "of": "egg"}],
             "bounds": [[-1, -1, -1], [1, 1, 1]]},
  "fit": {"type": "variational", "points": "ring.xyz", "normal_offset": 0.01, "margin": 0.1},
  "scan": {"type": "mpu", "points": "ring.xyz", "accuracy": 0.01, "support": 0.75, "max_depth": 4, "min_points": 15},
  "voxels": {"type": "vdb", "file": "torus.vdb", "grid": "surface"},
  "all": {"type": "union", "of": ["tube", "spike", "grown", "moved", "egg", "gem", "cubic", "round", "blobs", "stick", "hoop",
                                  "arm", "half", "hollow", "fit", "scan", "voxels"], "lipschitz": 20}
 },
 "objects": [
  {"name": "part", "field": "cut", "material": "clay",
   "transform": {"translate": [0, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": 10}, "scale": 1}},
  {"field": "blend", "as": "mesh", "method": "marching_cubes", "resolution": 16, "material": "gold"},
  {"field": "tangle", "as": "particles", "count": 100, "seed": 1, "disc_scale": 0.9, "material": "coat"},
  {"field": "all", "material": "ramp", "transform": {"scale": [0.2, 0.2, 0.2]}},
  {"field": "ring", "material": "lamp", "transform": {"translate": [0, 2, 0]}},
  {"mesh": "tet.off", "smooth": false, "material": "glass",
   "transform": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}},
  {"vertices": [-4, -1, -4, 4, -1, -4, 4, -1, 4], "indices": [0, 2, 1], "material": "checks"},
  {"field": "ball", "material": "chrome", "transform": {"translate": [2, 0, 0]}},
  {"field": "ball", "material": "metal", "transform": {"translate": [-2, 0, 0]}}
 ],
 "lights": [
  {"type": "point", "position": [0, 3, 0], "intensity": [5, 5, 5]},
  {"type": "directional", "direction": [0, -1, 0], "irradiance": [1, 1, 1]},
  {"type": "quad", "corner": [-1, 3, -1], "edge1": [2, 0, 0], "edge2": [0, 0, 2], "radiance": [1, 1, 1],
   "two_sided": false},
  {"type": "disk", "center": [0, 3, 0], "normal": [0, -1, 0], "radius": 0.5, "radiance": [1, 1, 1], "two_sided": true},
  {"type": "environment", "file": "sky.exr", "scale": 1, "rotate": {"axis": [0, 1, 0], "angle": 20}}
 ]
})";
}

const char* alternativeScene() {
    return R"({
 "camera": {"from": [0, 0, 5], "to": [0, 0, 0], "fov": 30},
 "film": {"width": 8, "height": 6, "spp": 1, "sampler": "independent", "filter": {"type": "box", "radius": 0.5}},
 "integrator": {"type": "whitted", "max_depth": 3},
 "materials": {"clay": {"type": "diffuse"},
               "shiny": {"type": "conductor", "reflectance": [0.9, 0.8, 0.7]},
               "sheet": {"type": "dielectric", "thin": true, "transmittance": [0.9, 0.9, 0.9]}},
 "fields": {
  "dots": {"type": "variational", "boundary": [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]],
           "interior": [[0, 0, 0]], "exterior": [[2, 2, 2]], "values": [[0, 0, 3, 1.5]],
           "normals": [[0.7071, 0.7071, 0, 0.7071, 0.7071, 0]], "gradients": [[0, 0.7071, 0.7071, 0, 0.7071, 0.7071]]},
  "smooth": {"type": "variational", "normals": [[1, 0, 0, 1, 0, 0], [-1, 0, 0, -1, 0, 0], [0, 1, 0, 0, 1, 0],
                                                [0, -1, 0, 0, -1, 0], [0, 0, 1, 0, 0, 1], [0, 0, -1, 0, 0, -1]],
             "hermite": true},
  "sampled": {"type": "variational", "sample": {"type": "sphere", "radius": 1}, "count": 60},
  "joined": {"type": "variational", "blend": ["sampled", {"type": "variational", "sample": {"type": "sphere",
             "radius": 1, "center": [1.2, 0, 0]}, "count": 60}]},
  "meshed": {"type": "mpu", "mesh": "ball.off"},
  "rings": {"type": "smooth_intersection", "of": [{"type": "torus", "major": 1, "minor": 0.3}, "dots"], "radius": 0.1},
  "bite": {"type": "smooth_difference", "of": ["smooth", {"type": "sphere", "radius": 0.5, "center": [1, 0, 0]}],
           "radius": 0.1}
 },
 "objects": [
  {"field": "joined", "as": "mesh", "method": "adaptive", "tolerance": 0.01, "material": "clay"},
  {"field": "rings", "as": "particles", "spacing": 0.1, "material": "shiny"},
  {"field": "bite", "material": "sheet"},
  {"field": "meshed", "material": "clay"},
  {"mesh": "tet.off", "smooth": true, "drop_degenerate": true, "material": "clay"}
 ],
 "lights": [{"type": "environment", "radiance": [1, 1, 1]}]
})";
}

std::string readSourceFile(const std::string& relative) {
    std::ifstream in(std::string(ISOTRACE_SOURCE_DIR) + "/" + relative, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

namespace {

/// About 100 points evenly over the unit sphere with outward normals.
std::string spherePoints() {
    std::ostringstream out;
    const int n = 100;
    const double golden = M_PI * (3 - std::sqrt(5.0));
    for (int i = 0; i < n; ++i) {
        const double y = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - y * y), phi = golden * i;
        const double x = r * std::cos(phi), z = r * std::sin(phi);
        out << x << ' ' << y << ' ' << z << ' ' << x << ' ' << y << ' ' << z << '\n';
    }
    return out.str();
}

/// A closed UV sphere of radius 1: 10 rings of 12 vertices and the poles.
std::string sphereMesh() {
    const int rings = 10, segments = 12, vertices = rings * segments + 2;
    std::ostringstream out;
    out << "OFF\n" << vertices << ' ' << segments * (rings + 1) << " 0\n0 1 0\n";
    for (int i = 1; i <= rings; ++i) {
        const double theta = M_PI * i / (rings + 1);
        for (int j = 0; j < segments; ++j) {
            const double phi = 2 * M_PI * j / segments;
            out << std::sin(theta) * std::cos(phi) << ' ' << std::cos(theta) << ' ' << std::sin(theta) * std::sin(phi)
                << '\n';
        }
    }
    out << "0 -1 0\n";
    auto at = [&](int ring, int j) { return 1 + ring * segments + (j % segments); };
    for (int j = 0; j < segments; ++j) out << "3 0 " << at(0, j + 1) << ' ' << at(0, j) << '\n';
    for (int i = 0; i + 1 < rings; ++i)
        for (int j = 0; j < segments; ++j)
            out << "4 " << at(i, j) << ' ' << at(i, j + 1) << ' ' << at(i + 1, j + 1) << ' ' << at(i + 1, j) << '\n';
    for (int j = 0; j < segments; ++j) out << "3 " << vertices - 1 << ' ' << at(rings - 1, j) << ' ' << at(rings - 1, j + 1) << '\n';
    return out.str();
}

}  // namespace

std::map<std::string, std::string> fixtureFiles() {
    return {
        {"scene.json", completeScene()},
        {"other.json", alternativeScene()},
        {"small.json", R"({"film": {"width": 12, "height": 8, "spp": 1},
  "materials": {"clay": {"type": "diffuse"}}, "fields": {"ball": {"type": "sphere", "radius": 1},
  "duo": {"type": "union", "of": ["ball", {"type": "box", "size": [1, 1, 1], "center": [1, 0, 0]}]}},
  "objects": [{"field": "ball", "material": "clay"}], "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})"},
        {"tet.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"},
        {"ball.off", sphereMesh()},
        {"ring.xyz", spherePoints()},
        {"sky.exr", readSourceFile("scenes/environments/sky.exr")},
        {"tiles.png", readSourceFile("scenes/textures/tiles.png")},
        {"torus.vdb", readSourceFile("tests/data/torus.vdb")},
    };
}

}  // namespace isotrace::testing
