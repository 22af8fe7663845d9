// The OpenVDB module (isotrace_openvdb.so): the one place that includes
// OpenVDB. It reads float level sets, proves the bounds of their trilinear
// interpolant block by block, and writes meshes as level sets through
// OpenVDB's mesh-to-volume conversion. Callers add the file and place to
// its messages.
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "geometry/openvdb_library.h"

namespace isotrace::geometry {

namespace {

using FloatTree = openvdb::FloatTree;
// Not registered with the tree: no lock on construction, one per call.
using Accessor = openvdb::tree::ValueAccessor<const FloatTree, /*IsSafe=*/false>;

void initializeOnce() {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

class GridVoxels final : public LevelSetVoxels {
public:
    explicit GridVoxels(openvdb::FloatGrid::ConstPtr grid) : grid_(std::move(grid)) {}
    void cellCorners(int i, int j, int k, float corners[8]) const override {
        Accessor voxels(grid_->tree());
        for (int c = 0; c < 8; ++c) corners[c] = voxels.getValue(openvdb::Coord(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2)));
    }

private:
    openvdb::FloatGrid::ConstPtr grid_;
};

// The index box of every voxel that holds something other than the
// background: leaf nodes, and tiles of another value (a level set's inside).
openvdb::CoordBBox storedBox(const openvdb::FloatGrid& grid) {
    openvdb::CoordBBox box;
    const FloatTree& tree = grid.tree();
    for (auto leaf = tree.cbeginLeaf(); leaf; ++leaf) box.expand(leaf->getNodeBoundingBox());
    auto value = tree.cbeginValueAll();
    value.setMaxDepth(FloatTree::DEPTH - 2);  // tiles only: leaves hold voxels
    for (; value; ++value)
        if (!value.isVoxelValue() && *value != tree.background()) box.expand(value.getBoundingBox());
    return box;
}

// The block's 9^3 footprint voxels: its own leaf region and the first layer
// of its seven neighbours beyond, each read from its leaf's buffer (or its
// one tile value), not voxel by voxel.
void readFootprint(Accessor& voxels, const openvdb::Coord& origin, float* v) {
    constexpr int n = kVoxelBlockCells, m = kFootprintSide;
    for (int c = 0; c < 8; ++c) {
        const int ox = n * (c & 1), oy = n * (c >> 1 & 1), oz = n * (c >> 2);
        const openvdb::Coord corner = origin.offsetBy(ox, oy, oz);
        const openvdb::FloatTree::LeafNodeType* leaf = voxels.probeConstLeaf(corner);
        const int xEnd = std::min(ox + n, m), yEnd = std::min(oy + n, m), zEnd = std::min(oz + n, m);
        if (!leaf) {
            const float tile = voxels.getValue(corner);
            for (int z = oz; z < zEnd; ++z)
                for (int y = oy; y < yEnd; ++y)
                    for (int x = ox; x < xEnd; ++x) v[(z * m + y) * m + x] = tile;
            continue;
        }
        // A leaf stores x slowest: offset (x << 6) + (y << 3) + z.
        const float* values = leaf->buffer().data();
        for (int z = oz; z < zEnd; ++z)
            for (int y = oy; y < yEnd; ++y)
                for (int x = ox; x < xEnd; ++x)
                    v[(z * m + y) * m + x] = values[((x - ox) << 6) + ((y - oy) << 3) + (z - oz)];
    }
}

constexpr float kNotANumber = std::numeric_limits<float>::quiet_NaN();

// One block's bounds from its footprint. Within a cell, each partial
// derivative is a blend of the differences along that axis's four edges:
// bounded by the largest of them. Taken cell by cell, as a surface's normal
// turns across the block.
VoxelBlockBounds footprintBounds(const float* v) {
    constexpr int n = kVoxelBlockCells, m = kFootprintSide;
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    bool finite = true;
    for (int i = 0; i < kFootprintVoxels; ++i) {
        finite = finite && std::isfinite(v[i]);
        lo = std::min(lo, v[i]);
        hi = std::max(hi, v[i]);
    }
    if (!finite) return {lo, hi, kNotANumber};
    // Blocks no surface crosses are only stepped over: the largest edge
    // difference along any axis, times sqrt(3), bounds them well enough.
    if (!(lo <= 0 && hi >= 0)) {
        float largest = 0;
        for (int z = 0; z < m; ++z)
            for (int y = 0; y < m; ++y) {
                const float* row = v + (z * m + y) * m;
                for (int x = 0; x < n; ++x) largest = std::max(largest, std::abs(row[x + 1] - row[x]));
                if (y < n)
                    for (int x = 0; x < m; ++x) largest = std::max(largest, std::abs(row[x + m] - row[x]));
                if (z < n)
                    for (int x = 0; x < m; ++x) largest = std::max(largest, std::abs(row[x + m * m] - row[x]));
            }
        return {lo, hi, float(double(largest) * std::sqrt(3.0) * (1 + 1e-6))};
    }
    // Each edge's difference once (in floats: the margin below covers their
    // rounding), then each cell's largest per axis.
    float ex[m][m][n], ey[m][n][m], ez[n][m][m];
    for (int z = 0; z < m; ++z)
        for (int y = 0; y < m; ++y)
            for (int x = 0; x < m; ++x) {
                const float here = v[(z * m + y) * m + x];
                if (x < n) ex[z][y][x] = std::abs(v[(z * m + y) * m + x + 1] - here);
                if (y < n) ey[z][y][x] = std::abs(v[(z * m + y + 1) * m + x] - here);
                if (z < n) ez[z][y][x] = std::abs(v[((z + 1) * m + y) * m + x] - here);
            }
    float worst = 0;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const float dx = std::max(std::max(ex[z][y][x], ex[z][y + 1][x]), std::max(ex[z + 1][y][x], ex[z + 1][y + 1][x]));
                const float dy = std::max(std::max(ey[z][y][x], ey[z][y][x + 1]), std::max(ey[z + 1][y][x], ey[z + 1][y][x + 1]));
                const float dz = std::max(std::max(ez[z][y][x], ez[z][y][x + 1]), std::max(ez[z][y + 1][x], ez[z][y + 1][x + 1]));
                worst = std::max(worst, dx * dx + dy * dy + dz * dz);
            }
    // A float difference, square and sum each round by at most half an ulp:
    // 1e-6 relative covers them, and the bound never understates the double.
    return {lo, hi, float(std::sqrt(double(worst)) * (1 + 1e-6))};
}

// One block's bounds: from its footprint where a leaf node is near, else
// from the up to 8 constant regions it touches.
VoxelBlockBounds blockBounds(Accessor& voxels, const openvdb::Coord& origin) {
    constexpr int n = kVoxelBlockCells;
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (int c = 0; c < 8; ++c) {
        const openvdb::Coord corner = origin.offsetBy(n * (c & 1), n * (c >> 1 & 1), n * (c >> 2));
        if (voxels.probeConstLeaf(corner)) {
            float footprint[kFootprintVoxels];
            readFootprint(voxels, origin, footprint);
            return footprintBounds(footprint);
        }
        const float v = voxels.getValue(corner);
        if (!std::isfinite(v)) return {v, v, kNotANumber};
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
    // Each region is one value; the interpolant moves between them by at
    // most hi - lo along each axis.
    return {lo, hi, float((hi - lo) * std::sqrt(3.0))};
}

std::string gridNames(openvdb::io::File& file) {
    std::string names;
    for (auto it = file.beginName(); it != file.endName(); ++it) names += (names.empty() ? "\"" : ", \"") + *it + "\"";
    return names.empty() ? "none" : names;
}

class Library final : public OpenVdbLibrary {
public:
    LevelSetGridData readLevelSet(const std::string& path, const std::string& askedName, double memoryBudget) override {
        initializeOnce();
        if (!std::filesystem::is_regular_file(path)) throw std::runtime_error("cannot open the file: no such file");
        openvdb::GridBase::Ptr base;
        std::string gridName = askedName;
        try {
            openvdb::io::File file(path);
            file.open(/*delayLoad=*/false);  // every voxel in memory: reads are then thread-safe
            if (gridName.empty()) {
                // Unnamed: the file's only grid.
                int count = 0;
                for (auto it = file.beginName(); it != file.endName(); ++it, ++count) gridName = *it;
                if (count != 1)
                    throw std::runtime_error("the file holds " + std::to_string(count) + " grids (" + gridNames(file) +
                                             "); name one with \"grid\"");
            }
            if (!file.hasGrid(gridName))
                throw std::runtime_error("no grid \"" + gridName + "\" in the file; its grids: " + gridNames(file));
            base = file.readGrid(gridName);
            file.close();
        } catch (const openvdb::Exception& e) {
            throw std::runtime_error(std::string("cannot read the file as OpenVDB: ") + e.what());
        } catch (const std::bad_alloc&) {
            throw std::runtime_error("cannot read the file as OpenVDB: it asks for more memory than there is (corrupt?)");
        } catch (const std::ios_base::failure& e) {
            throw std::runtime_error(std::string("cannot read the file as OpenVDB: ") + e.what());
        }
        const std::string what = "grid \"" + gridName + "\"";
        openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!grid) throw std::runtime_error(what + " holds " + base->valueType() + " values, not a float level set");
        if (grid->getGridClass() != openvdb::GRID_LEVEL_SET)
            throw std::runtime_error(what + " is a " + openvdb::GridBase::gridClassToString(grid->getGridClass()) +
                                     ", not a level set (class \"level set\"); fog volumes are not surfaces");
        const openvdb::math::Transform& transform = grid->transform();
        if (!transform.isLinear()) throw std::runtime_error(what + " has a non-linear (frustum) transform");
        if (!transform.hasUniformScale()) {
            const openvdb::Vec3d size = transform.voxelSize();
            std::ostringstream s;
            s << what << " has non-uniform voxels (" << size.x() << " x " << size.y() << " x " << size.z()
              << "); resample it to cubic voxels";
            throw std::runtime_error(s.str());
        }
        if (grid->activeVoxelCount() == 0) throw std::runtime_error(what + " is empty: it has no active voxels");
        const float background = grid->background();
        if (!std::isfinite(background) || background <= 0)
            throw std::runtime_error(what + " has background " + std::to_string(background) +
                                     "; a level set's is its band's positive half-width");

        LevelSetGridData data;
        data.voxelSize = transform.voxelSize().x();
        const openvdb::Mat4d m = transform.baseMap()->getAffineMap()->getMat4();
        // OpenVDB multiplies row vectors: world = index * m.
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) data.indexToWorld[3 * r + c] = m(c, r);
            data.indexOffset[r] = m(3, r);
        }
        data.background = background;
        data.activeVoxels = grid->activeVoxelCount();
        for (auto it = grid->beginMeta(); it != grid->endMeta(); ++it)
            if (it->second && it->second->typeName() == openvdb::StringMetadata::staticTypeName())
                data.metadata[it->first] = it->second->str();

        const openvdb::CoordBBox stored = storedBox(*grid);
        constexpr int n = kVoxelBlockCells;
        for (int a = 0; a < 3; ++a) {
            data.blockOrigin[a] = floorDiv(stored.min()[a], n) - 1;
            data.blockCount[a] = floorDiv(stored.max()[a], n) - data.blockOrigin[a] + 1;
        }
        // In doubles: a vast sparse grid's count overflows 64 bits.
        const double blocks = double(data.blockCount[0]) * double(data.blockCount[1]) * double(data.blockCount[2]);
        const double boundsBytes = blocks * sizeof(VoxelBlockBounds) * 8.0 / 7.0;  // and the pyramid above
        auto refuse = [&](double bytes, const char* needs) {
            std::ostringstream s;
            s << "grid \"" << gridName << "\" spans " << data.blockCount[0] * n << " x " << data.blockCount[1] * n << " x "
              << data.blockCount[2] * n << " voxels; its " << needs << " need " << bytes / double(1 << 20)
              << " MiB, more than the " << memoryBudget / double(1 << 20) << " MiB this machine's memory allows";
            throw std::runtime_error(s.str());
        };
        if (boundsBytes > memoryBudget) refuse(boundsBytes, "block bounds");
        const uint64_t blockCount = uint64_t(blocks);
        data.blocks.resize(blockCount);
        const FloatTree& tree = grid->tree();
        const int nx = data.blockCount[0], ny = data.blockCount[1];
        auto originOf = [&](uint64_t b) {
            const int x = int(b % nx), y = int(b / nx % ny), z = int(b / (uint64_t(nx) * ny));
            return openvdb::Coord(n * (data.blockOrigin[0] + x), n * (data.blockOrigin[1] + y), n * (data.blockOrigin[2] + z));
        };
        tbb::parallel_for(tbb::blocked_range<uint64_t>(0, blockCount, 64), [&](const tbb::blocked_range<uint64_t>& r) {
            Accessor voxels(tree);
            for (uint64_t b = r.begin(); b != r.end(); ++b) data.blocks[b] = blockBounds(voxels, originOf(b));
        });
        for (uint64_t b = 0; b < blockCount; ++b)
            if (std::isnan(data.blocks[b].gradient)) {
                const openvdb::Coord o = originOf(b);
                std::ostringstream s;
                s << what << " holds a value that is not a number, or infinite, among voxels (" << o.x() << ", "
                  << o.y() << ", " << o.z() << ") to +8";
                throw std::runtime_error(s.str());
            }
        // Footprints of the blocks a surface can cross.
        data.footprintOf.assign(blockCount, kNoFootprint);
        std::vector<uint64_t> surfaceBlocks;
        for (uint64_t b = 0; b < blockCount; ++b)
            if (data.blocks[b].lo <= 0 && data.blocks[b].hi >= 0) {
                data.footprintOf[b] = uint32_t(surfaceBlocks.size());
                surfaceBlocks.push_back(b);
            }
        const double footprintBytes = double(surfaceBlocks.size()) * kFootprintVoxels * sizeof(float) + blocks * 4.0;
        if (boundsBytes + footprintBytes > memoryBudget || surfaceBlocks.size() >= kNoFootprint)
            refuse(boundsBytes + footprintBytes, "block bounds and surface voxels");
        data.footprints.resize(surfaceBlocks.size() * kFootprintVoxels);
        tbb::parallel_for(tbb::blocked_range<size_t>(0, surfaceBlocks.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
            Accessor voxels(tree);
            for (size_t i = r.begin(); i != r.end(); ++i)
                readFootprint(voxels, originOf(surfaceBlocks[i]), data.footprints.data() + i * kFootprintVoxels);
        });
        data.voxels = std::make_shared<GridVoxels>(grid);
        return data;
    }

    LevelSetWriteReport writeLevelSet(const std::string& path, const IndexedMesh& mesh,
                                      const LevelSetWriteOptions& options) override {
        initializeOnce();
        std::vector<openvdb::Vec3s> points;
        points.reserve(mesh.vertices.size());
        for (const Vec3& v : mesh.vertices) points.emplace_back(float(v.x()), float(v.y()), float(v.z()));
        std::vector<openvdb::Vec3I> triangles;
        triangles.reserve(mesh.triangles.size());
        for (const auto& t : mesh.triangles) triangles.emplace_back(t[0], t[1], t[2]);
        const openvdb::math::Transform::Ptr transform = openvdb::math::Transform::createLinearTransform(options.voxelSize);
        openvdb::FloatGrid::Ptr grid =
            openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*transform, points, triangles, float(options.halfWidth));
        if (options.fog) openvdb::tools::sdfToFogVolume(*grid);
        grid->setName(options.gridName);
        openvdb::MetaMap fileMetadata;
        for (const auto& [key, value] : options.metadata) {
            grid->insertMeta(key, openvdb::StringMetadata(value));
            fileMetadata.insertMeta(key, openvdb::StringMetadata(value));
        }
        LevelSetWriteReport report;
        report.activeVoxels = grid->activeVoxelCount();
        report.leafNodes = grid->tree().leafCount();
        try {
            openvdb::io::File file(path);
            file.write(openvdb::GridCPtrVec{grid}, fileMetadata);
            file.close();
        } catch (const openvdb::Exception& e) {
            throw std::runtime_error(std::string("cannot write the file: ") + e.what());
        }
        std::error_code ignored;
        report.fileBytes = std::filesystem::file_size(path, ignored);
        return report;
    }
};

}  // namespace

}  // namespace isotrace::geometry

extern "C" isotrace::geometry::OpenVdbLibrary* isotraceOpenVdbLibrary() {
    static isotrace::geometry::Library library;
    return &library;
}
