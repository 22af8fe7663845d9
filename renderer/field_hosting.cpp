#include "renderer/field_hosting.h"

#include "geometry/errors.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace isotrace {

std::string userCacheDirectory() {
    if (const char* d = std::getenv("ISOTRACE_CACHE_DIR"); d && *d) return d;
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return (std::filesystem::path(d) / "isotrace").string();
    if (const char* d = std::getenv("HOME"); d && *d) return (std::filesystem::path(d) / ".cache" / "isotrace").string();
    return "";
}

std::shared_ptr<geometry::FitCache> processFitCache() {
    static const std::shared_ptr<geometry::FitCache> cache = std::make_shared<geometry::FitCache>(userCacheDirectory());
    return cache;
}

geometry::FieldLibraryOptions printingFieldOptions() {
    geometry::FieldLibraryOptions options;
    options.fitCache = processFitCache();
    options.warn = [](const std::string& file, const std::string& pointer, const std::string& message) {
        std::fprintf(stderr, "warning: %s: %s: %s\n", file.c_str(), pointer.c_str(), message.c_str());
    };
    return options;
}

geometry::FieldProgram compileSceneField(const std::string& scenePath, const std::string& field) {
    const geometry::Json root = geometry::parseJsonFile(scenePath);
    if (!root.is_object() || !root.contains("fields"))
        throw geometry::InputError(scenePath, "/fields", "the scene has no \"fields\"");
    const geometry::FieldLibrary library(root.at("fields"), "/fields", scenePath, printingFieldOptions());
    return library.compile(field);
}

}  // namespace isotrace
