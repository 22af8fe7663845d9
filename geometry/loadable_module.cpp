#include "geometry/loadable_module.h"
#include "geometry/errors.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace isotrace::geometry {

namespace {

std::vector<std::filesystem::path> moduleCandidates(const std::string& moduleName, const std::string& overrideVariable) {
    if (const char* forced = std::getenv(overrideVariable.c_str()); forced && *forced) return {forced};
    std::vector<std::filesystem::path> candidates;
    std::error_code ec;
    const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const std::filesystem::path folder = executable.parent_path();
        candidates = {folder / moduleName, folder.parent_path() / moduleName,
                      folder.parent_path() / "lib" / "isotrace" / moduleName};
    }
#ifdef ISOTRACE_INSTALLED_MODULE_DIR
    candidates.push_back(std::filesystem::path(ISOTRACE_INSTALLED_MODULE_DIR) / moduleName);
#endif
    return candidates;
}

}  // namespace

void* loadModuleEntryPoint(const ModuleDescription& m) {
    std::string tried;
    for (const std::filesystem::path& candidate : moduleCandidates(m.file, m.overrideVariable)) {
        // RTLD_LOCAL: the module's own dependencies stay out of the global
        // namespace; only the entry point is looked up.
        void* module = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!module) {
            tried += "\n  " + candidate.string() + ": " + dlerror();
            continue;
        }
        if (void* entry = dlsym(module, m.entryPoint.c_str())) return entry;
        tried += "\n  " + candidate.string() + ": no entry point " + m.entryPoint;
    }
    throw IoError("cannot load the " + m.library + " module " + m.file + " (needed for " + m.neededFor +
                  "); tried:" + tried);
}

}  // namespace isotrace::geometry
