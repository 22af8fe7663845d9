// Oriented point sets (.xyz / .pwn text: x y z nx ny nz per line).
#include "fuzz_support.h"

#include "geometry/variational/constraints.h"

using namespace isotrace;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::temporaryFile(data, size, ".xyz");
    fuzz::expectingUserErrors([&] { geometry::readOrientedPoints(path); });
    return 0;
}
