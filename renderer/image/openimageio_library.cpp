#include "renderer/image/openimageio_library.h"

#include "geometry/loadable_module.h"

namespace isotrace {

OpenImageIoLibrary& openImageIo() {
    static const geometry::ModuleDescription module{
        "OpenImageIO", "isotrace_openimageio.so", "isotraceOpenImageIoLibrary", "ISOTRACE_OPENIMAGEIO_MODULE",
        "images other than EXR and the PNG preview, and for textures"};
    return geometry::moduleLibrary<OpenImageIoLibrary>(module);
}

}  // namespace isotrace
