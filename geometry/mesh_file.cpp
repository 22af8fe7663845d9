#include "geometry/mesh_file.h"

#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "geometry/assimp_library.h"
#include "geometry/bounding_box.h"
#include "geometry/errors.h"

namespace isotrace::geometry {

std::string lowercaseExtension(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

namespace {

// The next line that holds something, without its comment; false at the end.
bool contentLine(std::istream& in, std::string& line, long& number) {
    while (std::getline(in, line)) {
        ++number;
        if (const size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);
        if (line.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
}

// Assimp's OFF reader clamps face indices into range and trusts the
// header's counts, so an OFF file is checked first: counts the file can
// hold, every vertex line present, every index a vertex. Errors name the
// line.
void checkOffFile(const std::string& path, uintmax_t bytes) {
    std::ifstream in(path);
    std::string line;
    long number = 0;
    if (!contentLine(in, line, number)) throw InputError(path, "", "empty OFF file");
    std::istringstream header(line);
    std::string magic;
    header >> magic;
    // COFF: OFF with a colour after each vertex (Princeton's shape
    // benchmark, many scanners); the colours are not read.
    if (magic != "OFF" && magic != "COFF")
        throw InputError(path, "line " + std::to_string(number), "expected \"OFF\" or \"COFF\"");
    long long vertices = -1, faces = -1;
    if (!(header >> vertices)) {  // the counts on a line of their own
        if (!contentLine(in, line, number)) throw InputError(path, "", "the OFF file ends before its counts");
        header = std::istringstream(line);
        header >> vertices;
    }
    const std::string countsAt = "line " + std::to_string(number);
    if (!(header >> faces) || vertices < 0 || faces < 0)
        throw InputError(path, countsAt, "expected the vertex and face counts (two whole numbers >= 0)");
    // A vertex takes at least 6 bytes ("0 0 0\n"), a face at least 8.
    if (double(vertices) * 6 + double(faces) * 8 > double(bytes))
        throw InputError(path, countsAt,
                         "the header claims " + std::to_string(vertices) + " vertices and " + std::to_string(faces) +
                             " faces, more than the file's " + std::to_string(bytes) + " bytes can hold");
    for (long long v = 0; v < vertices; ++v) {
        if (!contentLine(in, line, number))
            throw InputError(path, "", "the file ends after " + std::to_string(v) + " of its " + std::to_string(vertices) +
                                           " vertices");
        std::istringstream values(line);
        double x, y, z;
        if (!(values >> x >> y >> z))
            throw InputError(path, "line " + std::to_string(number), "expected a vertex: three numbers");
    }
    for (long long f = 0; f < faces; ++f) {
        if (!contentLine(in, line, number))
            throw InputError(path, "", "the file ends after " + std::to_string(f) + " of its " + std::to_string(faces) +
                                           " faces");
        const std::string at = "line " + std::to_string(number);
        std::istringstream values(line);
        long long n = 0;
        if (!(values >> n) || n < 3 || n > vertices)
            throw InputError(path, at, "expected a face: a corner count of 3 or more, then its vertex indices");
        for (long long k = 0; k < n; ++k) {
            long long index = -1;
            if (!(values >> index)) throw InputError(path, at, "face " + std::to_string(f) + " lists fewer than " + std::to_string(n) + " vertices");
            if (index < 0 || index >= vertices)
                throw InputError(path, at, "face " + std::to_string(f) + " refers to vertex " + std::to_string(index) +
                                               ", but there are " + std::to_string(vertices));
        }
    }
}

// Assimp allocates what a PLY header claims before it reads: the counts
// must fit in the file (a vertex takes at least 3 bytes, a face 1). And it
// never returns from a header without "end_header" (found by fuzzing).
void checkPlyHeader(const std::string& path, uintmax_t bytes) {
    constexpr long kMaxHeaderLines = 1000;
    std::ifstream in(path, std::ios::binary);
    std::string line;
    long number = 0;
    while (std::getline(in, line) && number < kMaxHeaderLines) {
        ++number;
        std::istringstream words(line);
        std::string word, name;
        long long count = 0;
        words >> word;
        if (word == "end_header") return;
        if (word != "element" || !(words >> name >> count)) continue;
        const double least = name == "vertex" ? 3.0 : 1.0;
        if (count < 0 || double(count) * least > double(bytes))
            throw InputError(path, "line " + std::to_string(number),
                             "the header claims " + std::to_string(count) + " " + name + " elements, more than the file's " +
                                 std::to_string(bytes) + " bytes can hold");
    }
    throw InputError(path, "line " + std::to_string(number),
                     "no \"end_header\" line by here: not a complete PLY header");
}

}  // namespace

IndexedMesh readMeshFile(const std::string& path, std::vector<std::array<float, 2>>* uvs) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "", "mesh file not found");
    const std::string extension = lowercaseExtension(path);
    if (extension != ".obj" && extension != ".off" && extension != ".ply")
        throw InputError(path, "", "unknown mesh format \"" + extension + "\" (isotrace reads .obj, .off and .ply)");
    const uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (extension == ".off") checkOffFile(path, bytes);
    if (extension == ".ply") checkPlyHeader(path, bytes);
    AssimpLibrary& assimp = assimpLibrary();  // a module that cannot load is not the file's fault
    MeshFileContents contents;
    try {
        contents = assimp.read(path);
    } catch (const std::runtime_error& e) {
        throw InputError(path, "", std::string("cannot read mesh: ") + e.what());
    }
    IndexedMesh mesh;
    bool everyPartHasUvs = !contents.parts.empty();
    for (const MeshFileContents::Part& part : contents.parts) everyPartHasUvs &= part.uvs.size() == part.vertices.size();
    if (uvs) uvs->clear();
    for (const MeshFileContents::Part& part : contents.parts) {
        const uint32_t base = static_cast<uint32_t>(mesh.vertices.size()), count = uint32_t(part.vertices.size());
        for (uint32_t v = 0; v < count; ++v) {
            const Vec3& p = part.vertices[v];
            if (!p.allFinite())
                throw InputError(path, "vertex " + std::to_string(v), "vertex coordinate is not a finite number");
            mesh.vertices.push_back(p);
            if (uvs && everyPartHasUvs) {
                const std::array<float, 2>& uv = part.uvs[v];
                if (!std::isfinite(uv[0]) || !std::isfinite(uv[1]))
                    throw InputError(path, "vertex " + std::to_string(v), "texture coordinate is not a finite number");
                uvs->push_back(uv);
            }
        }
        const uint32_t* face = part.indices.data();
        for (size_t f = 0; f < part.faceSizes.size(); face += part.faceSizes[f], ++f) {
            const uint32_t size = part.faceSizes[f];
            for (uint32_t k = 0; k < size; ++k)
                if (face[k] >= count)
                    throw InputError(path, "face " + std::to_string(f),
                                     "refers to vertex " + std::to_string(face[k]) + " of " + std::to_string(count));
            for (uint32_t k = 2; k < size; ++k) mesh.triangles.push_back({base + face[0], base + face[k - 1], base + face[k]});
        }
    }
    if (mesh.triangles.empty()) throw InputError(path, "", "mesh has no triangles");
    return mesh;
}

std::vector<Vec3> areaWeightedVertexNormals(const IndexedMesh& mesh) {
    std::vector<Vec3> sum(mesh.vertices.size(), Vec3::Zero());
    for (const auto& t : mesh.triangles) {
        // The cross product's length is twice the area: area weighting for free.
        const Vec3 n = (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
        for (uint32_t v : t) sum[v] += n;
    }
    for (Vec3& n : sum) n = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(0, 1, 0);
    return sum;
}

MeshRepair weldCoincidentVertices(IndexedMesh& mesh, double relativeTolerance) {
    MeshRepair repair;
    if (mesh.vertices.empty()) return repair;
    Box3 box;
    for (const Vec3& v : mesh.vertices) box.extend(v);
    const double tolerance = relativeTolerance * std::max(box.extent().norm(), 1e-300);
    // Cells of side `tolerance`: a vertex's twins lie in the 27 cells around it.
    auto cellOf = [&](const Vec3& p) {
        const Vec3 c = (p - box.lower) / tolerance;
        return std::array<int64_t, 3>{int64_t(std::floor(c.x())), int64_t(std::floor(c.y())), int64_t(std::floor(c.z()))};
    };
    struct CellHash {
        size_t operator()(const std::array<int64_t, 3>& c) const {
            return size_t(c[0] * 73856093) ^ size_t(c[1] * 19349663) ^ size_t(c[2] * 83492791);
        }
    };
    std::unordered_map<std::array<int64_t, 3>, std::vector<uint32_t>, CellHash> cells;
    std::vector<uint32_t> representative(mesh.vertices.size());
    for (uint32_t v = 0; v < mesh.vertices.size(); ++v) {
        const auto c = cellOf(mesh.vertices[v]);
        uint32_t found = v;
        for (int dx = -1; dx <= 1 && found == v; ++dx)
            for (int dy = -1; dy <= 1 && found == v; ++dy)
                for (int dz = -1; dz <= 1 && found == v; ++dz) {
                    const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == cells.end()) continue;
                    for (uint32_t w : it->second)
                        if ((mesh.vertices[w] - mesh.vertices[v]).norm() <= tolerance) {
                            found = w;
                            break;
                        }
                }
        representative[v] = found;
        if (found == v) cells[c].push_back(v);
        else ++repair.weldedVertices;
    }
    if (repair.weldedVertices == 0 && mesh.triangles.empty()) return repair;
    std::vector<std::array<uint32_t, 3>> kept;
    kept.reserve(mesh.triangles.size());
    for (std::array<uint32_t, 3> t : mesh.triangles) {
        for (uint32_t& i : t) i = representative[i];
        const Vec3 e1 = mesh.vertices[t[1]] - mesh.vertices[t[0]], e2 = mesh.vertices[t[2]] - mesh.vertices[t[0]];
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || !(e1.cross(e2).norm() > 0)) {
            ++repair.droppedTriangles;
            continue;
        }
        kept.push_back(t);
    }
    mesh.triangles = std::move(kept);
    return repair;
}

}  // namespace isotrace::geometry
