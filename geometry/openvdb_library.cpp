#include "geometry/openvdb_library.h"

#include "geometry/loadable_module.h"

namespace isotrace::geometry {

OpenVdbLibrary& openVdbLibrary() {
    static const ModuleDescription module{"OpenVDB", "isotrace_openvdb.so", "isotraceOpenVdbLibrary",
                                          "ISOTRACE_OPENVDB_MODULE", "VDB level sets (.vdb)"};
    return moduleLibrary<OpenVdbLibrary>(module);
}

}  // namespace isotrace::geometry
