// Images as `compare` and `merge` read them: the first byte picks the
// format (EXR, PNG, HDR), the rest is the file; a readable image is then
// compared with itself.
#include "fuzz_support.h"

#include "renderer/image/image_comparison.h"
#include "renderer/image/image_output.h"

using namespace isotrace;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* extensions[] = {".exr", ".png", ".hdr"};
    const std::string path = fuzz::temporaryFile(data + 1, size - 1, extensions[data[0] % 3]);
    fuzz::expectingUserErrors([&] {
        const Image image = readImage(path);
        compareImages(image, image);
    });
    return 0;
}
