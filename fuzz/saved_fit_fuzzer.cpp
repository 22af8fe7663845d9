// Saved variational fits (`isotrace fit` output), loaded as a scene's
// "fitted" field and evaluated.
#include "fuzz_support.h"

#include "geometry/description/field_parser.h"

using namespace isotrace;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::temporaryFile(data, size, ".fit.json");
    fuzz::expectingUserErrors([&] {
        const geometry::FieldLibrary library(geometry::Json{{"v", {{"type", "variational"}, {"fitted", path}}}}, "/fields",
                                             "/nonexistent-fuzz/scene.json");
        const geometry::FieldProgram field = library.compile("v");
        geometry::Vec3 g;
        field.valueAndGradient(geometry::Vec3(0.1, 0.2, 0.3), g);
        field.estimate(geometry::Box3(geometry::Vec3(-1, -1, -1), geometry::Vec3(1, 1, 1)));
    });
    return 0;
}
