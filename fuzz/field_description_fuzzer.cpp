// Field descriptions (a scene's "fields"): parse, compile every field, and
// ask each compiled field the four questions at a few points and boxes.
#include "fuzz_support.h"

#include "geometry/description/field_parser.h"

using namespace isotrace;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const geometry::Json json = geometry::Json::parse(data, data + size, nullptr, false);
    if (json.is_discarded()) return 0;
    fuzz::expectingUserErrors([&] {
        geometry::FieldLibraryOptions options;
        options.warn = [](const std::string&, const std::string&, const std::string&) {};
        const geometry::FieldLibrary library(json, "/fields", "/nonexistent-fuzz/scene.json", options);
        for (const std::string& name : library.names()) {
            fuzz::expectingUserErrors([&] {
                const geometry::FieldProgram field = library.compile(name);
                geometry::Vec3 g;
                for (const geometry::Vec3& p : {geometry::Vec3(0, 0, 0), geometry::Vec3(0.3, -0.7, 1.1)}) {
                    field.value(p);
                    field.valueAndGradient(p, g);
                }
                field.estimate(geometry::Box3(geometry::Vec3(-1, -1, -1), geometry::Vec3(1, 1, 1)));
            });
        }
    });
    return 0;
}
