#include "geometry/assimp_library.h"

#include "geometry/loadable_module.h"

namespace isotrace::geometry {

AssimpLibrary& assimpLibrary() {
    static const ModuleDescription module{"Assimp", "isotrace_assimp.so", "isotraceAssimpLibrary",
                                          "ISOTRACE_ASSIMP_MODULE", "polygon model files: .obj, .off and .ply"};
    return moduleLibrary<AssimpLibrary>(module);
}

}  // namespace isotrace::geometry
