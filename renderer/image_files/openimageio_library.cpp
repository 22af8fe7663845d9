#include "renderer/image_files/openimageio_library.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <stdexcept>

namespace isotrace {

namespace {

constexpr const char* kModuleName = "isotrace_openimageio.so";
constexpr const char* kEntryPoint = "isotraceOpenImageIoLibrary";

std::vector<std::filesystem::path> moduleCandidates() {
    if (const char* forced = std::getenv("ISOTRACE_OPENIMAGEIO_MODULE"); forced && *forced) return {forced};
    std::error_code ec;
    const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    const std::filesystem::path folder = executable.parent_path();
    return {folder / kModuleName, folder.parent_path() / kModuleName, folder.parent_path() / "lib" / "isotrace" / kModuleName};
}

OpenImageIoLibrary* load() {
    std::string tried;
    for (const std::filesystem::path& candidate : moduleCandidates()) {
        // RTLD_LOCAL: OpenImageIO's dependencies stay out of the global
        // namespace; only the entry point is looked up.
        void* module = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!module) {
            tried += "\n  " + candidate.string() + ": " + dlerror();
            continue;
        }
        using Entry = OpenImageIoLibrary* (*)();
        if (auto entry = reinterpret_cast<Entry>(dlsym(module, kEntryPoint))) return entry();
        tried += "\n  " + candidate.string() + ": no entry point " + kEntryPoint;
    }
    throw std::runtime_error(std::string("cannot load the OpenImageIO module ") + kModuleName +
                             " (needed for images other than EXR and the PNG preview, and for textures); tried:" +
                             tried);
}

}  // namespace

OpenImageIoLibrary& openImageIo() {
    // Loaded once per process (a failure is retried, so the error repeats).
    static OpenImageIoLibrary* library = nullptr;
    static std::mutex guard;
    std::lock_guard<std::mutex> lock(guard);
    if (!library) library = load();
    return *library;
}

}  // namespace isotrace
