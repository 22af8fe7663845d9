#include "renderer/scene_loader.h"

#include <gtest/gtest.h>

#include <cmath>

#include "renderer/render.h"
#include "support/scene_files.h"

using namespace isotrace;
using isotrace::testing::sceneError;
using isotrace::testing::TemporaryFolder;

namespace {

// A valid scene with one replaceable part: "%OBJECTS%", "%FILM%" etc.
std::string scene(const std::string& film = R"({"width": 32, "height": 24, "spp": 1})",
                  const std::string& objects = R"([{"field": "ball", "material": "clay"}])",
                  const std::string& extra = "") {
    return R"({"camera": {"from": [0, 0, 5], "to": [0, 0, 0], "fov": 40},
               "film": )" + film + R"(,
               "materials": {"clay": {"type": "diffuse", "albedo": [0.5, 0.5, 0.5]}},
               "fields": {"ball": {"type": "sphere", "radius": 1}},
               "objects": )" + objects + extra + R"(,
               "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";
}

void expectError(const std::string& error, const std::string& where, const std::string& what) {
    isotrace::testing::expectNamedError(error, where, what);
}

}  // namespace

TEST(SceneLoader, LoadsAValidScene) {
    TemporaryFolder folder;
    EXPECT_EQ(sceneError(folder, scene()), "");
}

TEST(SceneLoader, MissingFile) {
    try {
        loadScene("/nonexistent/scene.json");
        FAIL();
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json: cannot open"), std::string::npos) << e.what();
    }
}

TEST(SceneLoader, UnreadableFile) {
    TemporaryFolder folder;
    // A folder where a file is expected cannot be read, even by root.
    std::filesystem::create_directory(folder.file("scene.json"));
    try {
        loadScene(folder.file("scene.json"));
        FAIL();
    } catch (const geometry::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("scene.json"), std::string::npos);
    }
}

TEST(SceneLoader, MalformedJsonNamesLineAndColumn) {
    TemporaryFolder folder;
    expectError(sceneError(folder, "{\n  \"film\": {\"width\": 32,,\n}"), "line 2, column 24", "malformed JSON");
}

TEST(SceneLoader, NumberTooLargeForADouble) {
    TemporaryFolder folder;
    expectError(sceneError(folder, "{\"film\": {\"width\": 1e999}}"), "line 1, column 20", "number overflow");
}

TEST(SceneLoader, WrongTypes) {
    TemporaryFolder folder;
    expectError(sceneError(folder, scene(R"({"width": "wide"})")), "/film/width", "expected a whole number");
    expectError(sceneError(folder, scene(R"({"width": 32.5})")), "/film/width", "expected a whole number");
    expectError(sceneError(folder, scene(R"([1, 2])")), "/film", "expected an object");
    expectError(sceneError(folder, scene("{}", R"({"field": "ball"})")), "/objects", "expected an array");
}

TEST(SceneLoader, UnknownKeysSuggestTheNearest) {
    TemporaryFolder folder;
    expectError(sceneError(folder, scene(R"({"widht": 32})")), "/film/widht", "did you mean \"width\"");
    expectError(sceneError(folder, scene("{}", R"([{"field": "ball", "material": "clay", "matrial": 1}])")),
                "/objects/0/matrial", "unknown key");
}

TEST(SceneLoader, UnknownMaterialAndFieldNames) {
    TemporaryFolder folder;
    expectError(sceneError(folder, scene("{}", R"([{"field": "ball", "material": "cla"}])")), "/objects/0/material",
                "unknown material \"cla\" (did you mean \"clay\"?)");
    expectError(sceneError(folder, scene("{}", R"([{"field": "bal", "material": "clay"}])")), "/objects/0/field",
                "unknown field \"bal\"");
}

TEST(SceneLoader, ZeroOrNegativeSizesAndSampleCounts) {
    TemporaryFolder folder;
    expectError(sceneError(folder, scene(R"({"width": 0})")), "/film/width", "between 1 and");
    expectError(sceneError(folder, scene(R"({"height": -4})")), "/film/height", "between 1 and");
    expectError(sceneError(folder, scene(R"({"spp": 0})")), "/film/spp", "between 1 and");
}

TEST(SceneLoader, ImageTooLargeForMemoryIsRefusedWithTheEstimate) {
    TemporaryFolder folder;
    expectError(sceneError(folder, scene(R"({"width": 65536, "height": 65536})")), "/film", "GiB");
}

TEST(SceneLoader, MissingMeshFile) {
    TemporaryFolder folder;
    expectError(sceneError(folder, scene("{}", R"([{"mesh": "nothere.obj", "material": "clay"}])")), "/objects/0/mesh",
                "mesh file not found");
}

TEST(SceneLoader, CorruptMeshFile) {
    TemporaryFolder folder;
    folder.write("broken.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n");  // promises more than it has
    expectError(sceneError(folder, scene("{}", R"([{"mesh": "broken.off", "material": "clay"}])")), "/objects/0/mesh",
                "broken.off");
    folder.write("noise.obj", "this is not a mesh\n\x01\x02\x03");
    expectError(sceneError(folder, scene("{}", R"([{"mesh": "noise.obj", "material": "clay"}])")), "/objects/0/mesh",
                "noise.obj");
}

TEST(SceneLoader, LoadsMeshFilesOfEachFormat) {
    TemporaryFolder folder;
    folder.write("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    folder.write("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    folder.write("t.ply",
                 "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    for (const char* file : {"t.off", "t.obj", "t.ply"})
        EXPECT_EQ(sceneError(folder, scene("{}", std::string(R"([{"mesh": ")") + file + R"(", "material": "clay"}])")), "")
            << file;
}

TEST(SceneLoader, DegenerateTriangles) {
    TemporaryFolder folder;
    const std::string objects = R"([{"vertices": [0,0,0, 1,0,0, 2,0,0, 0,1,0], "indices": [0,1,3, 0,1,2], "material": "clay")";
    expectError(sceneError(folder, scene("{}", objects + "}]")), "/objects/0/indices", "triangle 1 is degenerate");
    EXPECT_EQ(sceneError(folder, scene("{}", objects + R"(, "drop_degenerate": true}])")), "");
    expectError(sceneError(folder, scene("{}", R"([{"vertices": [0,0,0, 1,0,0, 0,1,0], "indices": [0,1,7], "material": "clay"}])")),
                "/objects/0/indices", "refers to vertex 7");
}

TEST(SceneLoader, EmptyScene) {
    TemporaryFolder folder;
    expectError(sceneError(folder, scene("{}", "[]")), "/objects", "the scene is empty");
    expectError(sceneError(folder, "{}"), "/objects", "missing required key");
}

TEST(SceneLoader, InvalidFieldInsideAScene) {
    TemporaryFolder folder;
    const std::string text = R"({"materials": {"m": {"type": "diffuse"}},
        "fields": {"a": {"type": "union", "of": ["b"]}, "b": {"type": "union", "of": ["a"]}},
        "objects": [{"field": "a", "material": "m"}]})";
    expectError(sceneError(folder, text), "/fields/", "cycle in the field graph");
}

TEST(SceneLoader, TransformsOfEveryForm) {
    TemporaryFolder folder;
    auto withTransform = [&](const std::string& t) {
        return scene("{}", R"([{"field": "ball", "material": "clay", "transform": )" + t + "}]");
    };
    EXPECT_EQ(sceneError(folder, withTransform(R"({"translate": [1, 0, 0], "rotate": {"axis": [0, 1, 0], "angle": 45}, "scale": 2})")), "");
    EXPECT_EQ(sceneError(folder, withTransform(R"({"matrix": [[1,0,0,1],[0,1,0,0],[0,0,1,0],[0,0,0,1]]})")), "");
    expectError(sceneError(folder, withTransform(R"({"scale": 0})")), "/objects/0/transform/scale", "greater than 0");
    expectError(sceneError(folder, withTransform(R"({"matrix": [[1,0,0,0],[0,0,0,0],[0,0,1,0],[0,0,0,1]]})")),
                "/objects/0/transform", "singular");
    expectError(sceneError(folder, withTransform(R"({"matrix": [[1,0,0,1],[0,1,0,0],[0,0,1,0],[0,0,1,1]]})")),
                "/objects/0/transform/matrix", "affine");
}

TEST(SceneLoader, BadMeshSettingsOfFieldObjects) {
    TemporaryFolder folder;
    auto asMesh = [&](const std::string& keys) {
        return scene("{}", R"([{"field": "ball", "material": "clay", "as": "mesh", )" + keys + "}]");
    };
    expectError(sceneError(folder, asMesh(R"("method": "dual")")), "/objects/0/method", "valid values: \"adaptive\", \"marching_cubes\"");
    expectError(sceneError(folder, asMesh(R"("resolution": 0)")), "/objects/0/resolution", "between 1 and");
    expectError(sceneError(folder, asMesh(R"("resolution": 8192)")), "/objects/0", "GiB");
    expectError(sceneError(folder, asMesh(R"("tolerance": -0.1)")), "/objects/0/tolerance", "greater than 0");
    expectError(sceneError(folder, scene("{}", R"([{"field": "ball", "material": "clay", "as": "triangles"}])")),
                "/objects/0/as", "unknown value \"triangles\"");
    const std::string unbounded = R"({"materials": {"m": {"type": "diffuse"}}, "fields": {"floor": {"type": "plane"}},
        "objects": [{"field": "floor", "material": "m", "as": "mesh"}]})";
    expectError(sceneError(folder, unbounded), "/objects/0", "unbounded");
}

// Embree aborts on rays it cannot represent (origins past 1.8e18, non-finite
// values); such cameras, filters and transforms are errors at their key.
TEST(SceneLoader, UnrepresentableRaysAreRefusedAtTheirKey) {
    TemporaryFolder folder;
    auto withCamera = [](const std::string& camera) {
        std::string s = scene();
        const std::string original = R"({"from": [0, 0, 5], "to": [0, 0, 0], "fov": 40})";
        s.replace(s.find(original), original.size(), camera);
        return s;
    };
    expectError(sceneError(folder, withCamera(R"({"from": [0, 0, 9.2e18], "to": [0, 0, 0]})")), "/camera/from",
                "single-precision rays");
    expectError(sceneError(folder, withCamera(R"({"from": [0, 0, 5], "to": [0, 0, 0], "up": [0, 1e300, 0]})")),
                "/camera/up", "single-precision rays");
    expectError(sceneError(folder, withCamera(R"({"from": [0, 0, 5], "to": [0, 0, 0], "aperture": 1e300})")),
                "/camera/aperture", "single-precision rays");
    expectError(sceneError(folder, scene(R"({"width": 8, "height": 8, "spp": 1, "filter": {"type": "box", "radius": 1e308}})")),
                "/film/filter/radius", "at most 1000 pixels");
    expectError(sceneError(folder, scene(R"({"width": 8, "height": 8, "spp": 1})",
                                         R"([{"field": "ball", "material": "clay", "transform": {"scale": 1e12}}])")),
                "/objects/0/transform", "single-precision rays");
    expectError(sceneError(folder, scene(R"({"width": 8, "height": 8, "spp": 1})",
                                         R"([{"field": "ball", "material": "clay", "transform": {"scale": [1e-10, 1e5, 1e5]}}])")),
                "/objects/0/transform", "single-precision rays");
}

// Objects that show the same mesh file share one mesh (Embree instances,
// not copies), and the image is that of inline copies of the triangles
// moved by hand.
TEST(SceneLoader, ObjectsOfOneMeshFileShareOneMesh) {
    TemporaryFolder folder;
    folder.write("tri.obj", "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0 0.5 0\nf 1 2 3\n");
    std::string shared = "[", copied = "[";
    for (int i = 0; i < 3; ++i) {
        const double x = 1.2 * (i - 1);
        const std::string translate = R"(, "transform": {"translate": [)" + std::to_string(x) + R"(, 0, 0]}})";
        shared += std::string(i ? ", " : "") + R"({"mesh": "tri.obj", "material": "clay")" + translate;
        copied += std::string(i ? ", " : "") + R"({"vertices": [)" + std::to_string(x - 0.5) + ", -0.5, 0, " +
                  std::to_string(x + 0.5) + ", -0.5, 0, " + std::to_string(x) + R"(, 0.5, 0], "indices": [0, 1, 2], "material": "clay"})";
    }
    shared += R"(, {"mesh": "tri.obj", "material": "clay", "smooth": true, "transform": {"translate": [0, 1.2, 0]}}])";
    copied += R"(, {"vertices": [-0.5, 0.7, 0, 0.5, 0.7, 0, 0, 1.7, 0], "indices": [0, 1, 2], "material": "clay", "smooth": true}])";
    const std::string film = R"({"width": 48, "height": 32, "spp": 4})";
    const auto instanced = isotrace::testing::loadSceneText(folder, scene(film, shared));
    const auto copies = isotrace::testing::loadSceneText(folder, scene(film, copied));
    ASSERT_EQ(instanced->objects.size(), 4u);
    EXPECT_EQ(instanced->meshes.size(), 2u);  // flat and smooth: one each
    EXPECT_EQ(copies->meshes.size(), 4u);
    const Image a = render(*instanced, {.threads = 2, .seed = 1, .quiet = true});
    const Image b = render(*copies, {.threads = 2, .seed = 1, .quiet = true});
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    double difference = 0, total = 0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        difference += std::abs(a.rgb[i] - b.rgb[i]);
        total += b.rgb[i];
    }
    // Instancing moves rays rather than triangles: single-precision round-off
    // moves a few silhouette samples, nothing more.
    EXPECT_LT(difference, 1e-3 * total);
    EXPECT_GT(total, 0.0);
}

// Texture coordinates come from mesh files (OBJ vt, PLY s t) and inline
// "uvs", and a hit interpolates them over its triangle.
TEST(SceneLoader, MeshesCarryTextureCoordinatesToTheirHits) {
    TemporaryFolder folder;
    folder.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n");
    folder.write("quad.ply",
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float s\nproperty float t\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
                 "-1 -1 0 0 0\n1 -1 0 1 0\n1 1 0 1 1\n-1 1 0 0 1\n3 0 1 2\n3 0 2 3\n");
    for (const std::string object :
         {R"({"mesh": "quad.obj", "material": "clay"})", R"({"mesh": "quad.ply", "material": "clay"})",
          R"({"vertices": [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0], "indices": [0, 1, 2, 0, 2, 3],
              "uvs": [0, 0, 1, 0, 1, 1, 0, 1], "material": "clay"})"}) {
        const auto loaded = isotrace::testing::loadSceneText(folder, scene("{}", "[" + object + "]"));
        ASSERT_EQ(loaded->meshes.size(), 1u) << object;
        EXPECT_FALSE(loaded->meshes[0]->uvs.empty()) << object;
        SurfaceHit hit;
        ASSERT_TRUE(loaded->intersect(Ray{Vec3(0.5, -0.2, 3), Vec3(0, 0, -1)}, INFINITY, hit)) << object;
        ASSERT_TRUE(hit.hasUv) << object;
        EXPECT_NEAR(hit.uv.x(), 0.75, 1e-6) << object;
        EXPECT_NEAR(hit.uv.y(), 0.4, 1e-6) << object;
        EXPECT_NEAR(hit.uvPerLength, 0.5, 1e-6) << object;  // a 2 m quad spans one unit of uv
    }
    const auto plain = isotrace::testing::loadSceneText(
        folder, scene("{}", R"([{"vertices": [-1, -1, 0, 1, -1, 0, 1, 1, 0], "indices": [0, 1, 2], "material": "clay"}])"));
    SurfaceHit hit;
    ASSERT_TRUE(plain->intersect(Ray{Vec3(0.5, -0.2, 3), Vec3(0, 0, -1)}, INFINITY, hit));
    EXPECT_FALSE(hit.hasUv);
    expectError(sceneError(folder, scene("{}", R"([{"vertices": [-1, -1, 0, 1, -1, 0, 1, 1, 0], "indices": [0, 1, 2],
        "uvs": [0, 0, 1], "material": "clay"}])")), "/objects/0/uvs", "expected u v per vertex: 6 numbers, found 3");
}
