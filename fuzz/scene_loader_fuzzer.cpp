// Whole scene files: everything the loader reads, builds and commits to
// Embree (files they name do not exist here).
#include "fuzz_support.h"

#include "renderer/scene_loader.h"

using namespace isotrace;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const geometry::Json json = geometry::Json::parse(data, data + size, nullptr, false);
    if (json.is_discarded()) return 0;
    fuzz::expectingUserErrors([&] { loadSceneDescription(json, "/nonexistent-fuzz/scene.json"); });
    return 0;
}
