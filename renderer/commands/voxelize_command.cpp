// `isotrace voxelize`: a field of a scene to an OpenVDB file, as a
// narrow-band signed-distance level set (or a fog volume). Any field kind
// gets true distances in the band: the field is polygonized on the voxel
// grid (visiting only the cells its proven ranges say hold the surface, in
// parallel), and OpenVDB's mesh-to-volume conversion measures the distance
// to that surface.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include <tbb/task_arena.h>

#include "geometry/content_hash.h"
#include "geometry/description/field_parser.h"
#include "geometry/errors.h"
#include "geometry/mesh_file.h"
#include "geometry/meshing/polygonizer.h"
#include "geometry/openvdb_library.h"
#include "geometry/physical_memory.h"
#include "renderer/commands/command.h"
#include "renderer/field_hosting.h"
#include "renderer/image/image_output.h"
#include "renderer/platform/version.h"
#include "renderer/scene_loader.h"

namespace isotrace {

namespace {

struct VoxelizeCommand {
    std::string scene, field, output, grid = "surface";
    double voxelSize = 0.0, halfWidth = 3.0;
    int resolution = 0, threads = 0;
    bool fog = false, report = false;
};

constexpr int kDefaultResolution = 256;

// A surface as large as the six faces of its box crosses about 6 R^2 cells;
// the band holds 2 w voxels across it, each about 8 bytes in OpenVDB's leaves
// (value, masks, the leaves' partial fill), besides the mesh.
double estimateVoxelizeBytes(int resolution, double halfWidth) {
    const double surfaceCells = 6.0 * double(resolution) * double(resolution);
    return surfaceCells * 2.0 * halfWidth * 8.0 + geometry::estimatePolygonizeBytes(resolution);
}

int runVoxelize(const VoxelizeCommand& cmd) {
    if (geometry::lowercaseExtension(cmd.output) != ".vdb")
        throw geometry::InputError(cmd.output, "", "an OpenVDB file must end in .vdb");
    if (cmd.voxelSize > 0 && cmd.resolution > 0)
        throw geometry::InputError("command line", "", "give either --voxel-size or --resolution, not both");
    checkOutputPath(cmd.output, sceneInputFiles(cmd.scene));
    const std::string fieldPointer = geometry::jsonPointerAppend("/fields", cmd.field);
    const geometry::FieldProgram field = compileSceneField(cmd.scene, cmd.field);
    const geometry::Box3 bounds = field.bounds();
    if (!bounds.isFinite() || bounds.isEmpty())
        throw geometry::InputError(cmd.scene, fieldPointer, "the field is unbounded or empty; give it \"bounds\" to voxelize it");
    const double longest = bounds.extent().maxCoeff();
    const double wanted = cmd.voxelSize > 0 ? cmd.voxelSize : longest / (cmd.resolution > 0 ? cmd.resolution : kDefaultResolution);
    // Cells along the longest side, the polygonizer's grid: a cell is then
    // at most one voxel.
    const double cells = std::ceil(longest / wanted);
    const double bytes = cells <= geometry::kMaxPolygonizeResolution ? estimateVoxelizeBytes(int(cells), cmd.halfWidth) : INFINITY;
    if (!(bytes <= 0.5 * geometry::physicalMemoryBytes())) {
        char message[320];
        std::snprintf(message, sizeof message,
                      "a voxel size of %g makes %.0f voxels along the field's longest side (%g): about %.1f GiB for a "
                      "surface as large as its bounding box's faces, more than half of this machine's memory "
                      "(limit %d voxels)",
                      wanted, cells, longest, bytes / double(1 << 30), geometry::kMaxPolygonizeResolution);
        throw geometry::InputError("command line", "", message);
    }
    tbb::task_arena arena(cmd.threads > 0 ? cmd.threads : tbb::task_arena::automatic);
    const auto start = std::chrono::steady_clock::now();
    geometry::PolygonizeOptions options;
    options.resolution = std::max(1, int(cells));
    options.threads = cmd.threads;
    geometry::Polygonization surface;
    try {
        surface = geometry::polygonize(field, options);
    } catch (const std::invalid_argument& e) {
        throw geometry::InputError(cmd.scene, fieldPointer, e.what());
    }
    for (const std::string& w : surface.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (surface.mesh.triangles.empty())
        throw geometry::InputError(cmd.scene, fieldPointer, "the field has no surface inside its bounds: nothing to voxelize");
    const double voxelSize = longest / options.resolution;

    geometry::LevelSetWriteOptions write;
    write.voxelSize = voxelSize;
    write.halfWidth = cmd.halfWidth;
    write.gridName = cmd.grid;
    write.fog = cmd.fog;
    uint64_t hash = geometry::kFnvOffsetBasis;
    geometry::fnv1a64File(cmd.scene, hash);
    const geometry::Json scene = geometry::parseJsonFile(cmd.scene);
    write.metadata = {{"creator", "isotrace " + std::string(kVersion)},
                      {"isotrace:scene", std::filesystem::path(cmd.scene).filename().string()},
                      {"isotrace:scene_hash", geometry::hexDigest(hash)},
                      {"isotrace:field", cmd.field},
                      {"isotrace:field_description", scene.at("fields").at(cmd.field).dump()}};
    const std::filesystem::path out(cmd.output);
    const std::string temporary =
        (out.parent_path() / ("." + out.stem().string() + ".partial-" + std::to_string(getpid()) + ".vdb")).string();
    geometry::LevelSetWriteReport written;
    try {
        arena.execute([&] { written = geometry::openVdbLibrary().writeLevelSet(temporary, surface.mesh, write); });
        std::filesystem::rename(temporary, cmd.output);
    } catch (const std::exception& e) {
        std::error_code ignored;
        std::filesystem::remove(temporary, ignored);
        throw geometry::IoError(cmd.output, e.what());
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (cmd.report) {
        const geometry::Json report = {
            {"field", cmd.field},
            {"grid", cmd.grid},
            {"class", cmd.fog ? "fog volume" : "level set"},
            {"voxel_size", voxelSize},
            {"half_width_voxels", cmd.halfWidth},
            {"resolution", options.resolution},
            {"active_voxels", written.activeVoxels},
            {"leaf_nodes", written.leafNodes},
            {"file_bytes", written.fileBytes},
            {"polygonize_seconds", surface.seconds},
            {"seconds", seconds},
        };
        std::printf("%s\n", report.dump(2).c_str());
    }
    return 0;
}

}  // namespace

Subcommand addVoxelizeCommand(CLI::App& app) {
    auto c = std::make_shared<VoxelizeCommand>();
    CLI::App* sub = app.add_subcommand(
        "voxelize", "Write a field of a scene as an OpenVDB narrow-band level set (or fog volume) for other tools");
    sub->add_option("scene", c->scene, "Scene file whose \"fields\" hold the field")->required();
    sub->add_option("--field", c->field, "Name of the field")->required();
    sub->add_option("-o,--output", c->output, "Output file (.vdb)")->required();
    sub->add_option("--voxel-size", c->voxelSize, "Edge of a voxel in world units")->check(finitePositive());
    sub->add_option("--resolution", c->resolution,
                    "Voxels along the longest side of the field's bounds (default 256), instead of --voxel-size")
        ->check(CLI::Range(1, std::numeric_limits<int>::max()));
    sub->add_option("--half-width", c->halfWidth, "Half-width of the narrow band, in voxels (default 3)")
        ->check(CLI::Range(1.0, 64.0));
    sub->add_option("--grid", c->grid, "Name of the grid (default \"surface\")")->check([](const std::string& s) {
        return s.empty() ? std::string("a grid needs a name") : std::string();
    });
    sub->add_flag("--fog", c->fog, "Write a fog volume (density 1 inside) instead of a level set");
    sub->add_option("--threads", c->threads, "Worker threads (default: all cores)")->check(CLI::Range(1, 4096));
    sub->add_flag("--report", c->report, "Print the grid's size and the time taken as JSON");
    return {sub, [c] { return runVoxelize(*c); }};
}

}  // namespace isotrace
