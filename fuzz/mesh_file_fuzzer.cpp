// Polygon model files: the first byte picks the format (OFF, PLY, OBJ), the
// rest is the file, read by the geometry library's reader (variational
// fits) and the renderer's (mesh objects).
#include "fuzz_support.h"

#include "geometry/mesh_file.h"
#include "renderer/triangle_mesh.h"

using namespace isotrace;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* extensions[] = {".off", ".ply", ".obj"};
    const std::string path = fuzz::temporaryFile(data + 1, size - 1, extensions[data[0] % 3]);
    fuzz::expectingUserErrors([&] { geometry::readMeshFile(path); });
    fuzz::expectingUserErrors([&] { loadTriangleMesh(path); });
    return 0;
}
