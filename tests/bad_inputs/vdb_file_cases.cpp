// OpenVDB files a vdb field cannot read as a surface, made here with
// OpenVDB itself (grids of other types, classes and transforms), and
// voxelize requests that cannot be met.
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetSphere.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <limits>

#include "bad_inputs/bad_input_case.h"

namespace isotrace::testing {

namespace {

/// The bytes of a file holding `grid`.
std::string fileBytes(const openvdb::GridBase::Ptr& grid) {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("isotrace-corpus-grid-" + std::to_string(::getpid()) + ".vdb");
    {
        openvdb::io::File file(path.string());
        file.write({grid});
        file.close();
    }
    std::ifstream in(path, std::ios::binary);
    std::string bytes(std::istreambuf_iterator<char>(in), {});
    std::filesystem::remove(path);
    return bytes;
}

openvdb::FloatGrid::Ptr sphere() {
    openvdb::FloatGrid::Ptr grid = openvdb::tools::createLevelSetSphere<openvdb::FloatGrid>(1.0f, {0, 0, 0}, 0.2f, 3.0f);
    grid->setName("surface");
    return grid;
}

/// A scene whose field "v" reads `grid` of v.vdb, rendered.
BadInputCase readCase(const std::string& name, const std::string& bytes, const std::string& grid,
                      std::vector<std::string> mentions, bool writeFile = true) {
    const std::string gridKey = grid.empty() ? "" : R"(, "grid": ")" + grid + "\"";
    const std::string scene = R"({"film": {"width": 12, "height": 8, "spp": 1},
  "materials": {"clay": {"type": "diffuse"}}, "fields": {"v": {"type": "vdb", "file": "v.vdb")" +
                              gridKey + R"(}},
  "objects": [{"field": "v", "material": "clay"}], "lights": [{"type": "environment", "radiance": [1, 1, 1]}]})";
    mentions.insert(mentions.begin(), {"vdb.json", "/fields/v/file", "v.vdb"});
    std::map<std::string, std::string> files{{"vdb.json", scene}};
    if (writeFile) files["v.vdb"] = bytes;
    return makeCase(name, "render vdb.json -o out.exr --quiet", std::move(mentions), {}, std::move(files));
}

}  // namespace

std::vector<BadInputCase> vdbFileCases() {
    openvdb::initialize();
    std::vector<BadInputCase> cases;
    auto add = [&](BadInputCase c) { cases.push_back(std::move(c)); };
    const std::string torus = readSourceFile("tests/data/torus.vdb");

    add(readCase("vdb_missing_file", "", "", {"No such file"}, /*writeFile=*/false));
    add(readCase("vdb_missing_grid", torus, "density", {"no grid \"density\"", "\"surface\""}));
    add(readCase("vdb_text_file", "this is not an OpenVDB file\n", "", {"cannot read the file as OpenVDB"}));
    add(readCase("vdb_empty_file", "", "surface", {"cannot read the file as OpenVDB"}));
    add(readCase("vdb_truncated", torus.substr(0, torus.size() / 2), "surface", {"cannot read the file as OpenVDB"}));
    add(readCase("vdb_header_only", torus.substr(0, 64), "", {"OpenVDB"}));

    openvdb::FloatGrid::Ptr two = sphere();
    openvdb::FloatGrid::Ptr other = two->deepCopy();
    other->setName("other");
    {
        const std::filesystem::path path =
            std::filesystem::temp_directory_path() / ("isotrace-corpus-two-" + std::to_string(::getpid()) + ".vdb");
        openvdb::io::File file(path.string());
        file.write({two, other});
        file.close();
        std::ifstream in(path, std::ios::binary);
        add(readCase("vdb_two_grids_unnamed", std::string(std::istreambuf_iterator<char>(in), {}), "",
                     {"2 grids", "name one with \"grid\""}));
        std::filesystem::remove(path);
    }

    openvdb::DoubleGrid::Ptr doubles = openvdb::tools::createLevelSetSphere<openvdb::DoubleGrid>(1.0, {0, 0, 0}, 0.2, 3.0);
    doubles->setName("surface");
    add(readCase("vdb_double_grid", fileBytes(doubles), "surface", {"double values, not a float level set"}));

    openvdb::Vec3SGrid::Ptr vectors = openvdb::Vec3SGrid::create(openvdb::Vec3s(0, 0, 0));
    vectors->tree().setValue(openvdb::Coord(1, 2, 3), openvdb::Vec3s(1, 0, 0));
    vectors->setName("velocity");
    add(readCase("vdb_vector_grid", fileBytes(vectors), "velocity", {"vec3s values, not a float level set"}));

    openvdb::FloatGrid::Ptr fog = sphere();
    fog->setGridClass(openvdb::GRID_FOG_VOLUME);
    add(readCase("vdb_fog_volume", fileBytes(fog), "surface", {"fog volume, not a level set"}));

    openvdb::FloatGrid::Ptr stretched = sphere();
    stretched->setTransform(openvdb::math::Transform::createLinearTransform(
        openvdb::math::scale<openvdb::Mat4R>(openvdb::Vec3R(0.2, 0.4, 0.2))));
    add(readCase("vdb_nonuniform_voxels", fileBytes(stretched), "surface", {"non-uniform voxels", "0.2 x 0.4 x 0.2"}));

    openvdb::FloatGrid::Ptr frustum = sphere();
    frustum->setTransform(openvdb::math::Transform::createFrustumTransform(
        openvdb::BBoxd(openvdb::Vec3d(0, 0, 0), openvdb::Vec3d(10, 10, 10)), 0.5, 1.0, 0.1));
    add(readCase("vdb_frustum_transform", fileBytes(frustum), "surface", {"non-linear"}));

    openvdb::FloatGrid::Ptr empty = openvdb::FloatGrid::create(0.6f);
    empty->setGridClass(openvdb::GRID_LEVEL_SET);
    empty->setName("surface");
    add(readCase("vdb_empty_grid", fileBytes(empty), "surface", {"empty"}));

    openvdb::FloatGrid::Ptr poisoned = sphere();
    poisoned->tree().setValue(openvdb::Coord(0, 0, 5), std::numeric_limits<float>::quiet_NaN());
    add(readCase("vdb_nan_voxel", fileBytes(poisoned), "surface", {"not a number"}));

    openvdb::FloatGrid::Ptr vast = sphere();
    vast->tree().setValue(openvdb::Coord(40000000, -40000000, 40000000), 0.1f);
    add(readCase("vdb_vast_extent", fileBytes(vast), "surface", {"spans", "memory"}));

    // voxelize
    add(makeCase("voxelize_no_field", "voxelize small.json -o out.vdb", {"--field"}));
    add(makeCase("voxelize_unknown_field", "voxelize small.json --field cube -o out.vdb", {"cube"}));
    add(makeCase("voxelize_not_vdb", "voxelize small.json --field ball -o out.ply", {"out.ply", ".vdb"}));
    add(makeCase("voxelize_both_sizes", "voxelize small.json --field ball -o out.vdb --voxel-size 0.1 --resolution 20",
                 {"--voxel-size", "--resolution"}));
    add(makeCase("voxelize_voxel_size_nan", "voxelize small.json --field ball -o out.vdb --voxel-size nan", {"--voxel-size"}));
    add(makeCase("voxelize_voxel_size_negative", "voxelize small.json --field ball -o out.vdb --voxel-size -1",
                 {"--voxel-size"}));
    add(makeCase("voxelize_resolution_zero", "voxelize small.json --field ball -o out.vdb --resolution 0", {"--resolution"}));
    add(makeCase("voxelize_threads_zero", "voxelize small.json --field ball -o out.vdb --threads 0", {"--threads"}));
    add(makeCase("voxelize_missing_folder", "voxelize small.json --field ball -o nowhere/out.vdb", {"nowhere"}));
    add(makeCase("voxelize_half_width_zero", "voxelize small.json --field ball -o out.vdb --half-width 0", {"--half-width"}));
    add(makeCase("voxelize_grid_empty", "voxelize small.json --field ball -o out.vdb --grid ''", {"--grid"}));
    add(makeCase("voxelize_voxels_past_memory", "voxelize small.json --field ball -o out.vdb --voxel-size 1e-7",
                 {"voxel size", "memory"}));
    add(makeCase("voxelize_unbounded", "voxelize unbounded.json --field floor -o out.vdb", {"unbounded.json", "/fields/floor", "unbounded"},
                 {}, {{"unbounded.json", R"({"fields": {"floor": {"type": "plane", "normal": [0, 1, 0], "offset": 0}}})"}}));
    add(makeCase("voxelize_output_is_scene", "voxelize small.json --field ball -o small.json", {"small.json"}));
    add(makeCase("voxelize_output_is_input", "voxelize reads.json --field v -o torus.vdb", {"torus.vdb"}, {},
                 {{"reads.json", R"({"fields": {"v": {"type": "vdb", "file": "torus.vdb"}}})"}}));
    return cases;
}

}  // namespace isotrace::testing
