// Shared by the fuzz targets: inputs that must reach a file go through a
// per-process temporary file, and the errors isotrace reports to users as
// bad input (InputError, runtime_error, invalid_argument) are expected
// outcomes; anything else escaping a target (a logic error, bad_alloc, a
// crash, a sanitizer report) is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <stdexcept>
#include <string>

#include "geometry/errors.h"

namespace isotrace::fuzz {

/// Writes the bytes to /tmp/isotrace-fuzz-PID.EXT and returns the path.
inline std::string temporaryFile(const uint8_t* data, size_t size, const std::string& extension) {
    const std::string path = "/tmp/isotrace-fuzz-" + std::to_string(getpid()) + extension;
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path;
}

/// Runs `body`, treating the errors reported to users as expected.
template <class Body>
void expectingUserErrors(Body&& body) {
    try {
        body();
    } catch (const geometry::InputError&) {
    } catch (const std::invalid_argument&) {
    } catch (const std::runtime_error&) {
    }
}

}  // namespace isotrace::fuzz
