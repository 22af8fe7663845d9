#include "geometry/description/fit_cache.h"

#include <filesystem>

#include "geometry/atomic_file.h"
#include "geometry/description/variational_description.h"

namespace isotrace::geometry {

std::string FitCache::pathOf(const std::string& hash) const {
    return directory_.empty() ? "" : (std::filesystem::path(directory_) / ("variational-" + hash + ".json")).string();
}

std::shared_ptr<const VariationalField> FitCache::find(const std::string& hash) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = memory_.find(hash); it != memory_.end()) return it->second;
    }
    const std::string path = pathOf(hash);
    if (path.empty() || !std::filesystem::exists(path)) return nullptr;
    std::shared_ptr<const VariationalField> field;
    try {
        const Json j = parseJsonFile(path);
        if (j.value("source_hash", "") == hash)
            field = std::make_shared<const VariationalField>(variationalFieldFromJson(j, path));
    } catch (const std::exception&) {
        return nullptr;  // a damaged entry is refitted and rewritten
    }
    if (field) {
        std::lock_guard<std::mutex> lock(mutex_);
        memory_.emplace(hash, field);
    }
    return field;
}

void FitCache::store(const std::string& hash, std::shared_ptr<const VariationalField> field, const FitReport& report,
                     const Json& provenance) {
    if (const std::string path = pathOf(hash); !path.empty()) {
        try {
            std::filesystem::create_directories(std::filesystem::path(path).parent_path());
            writeFileAtomically(path, variationalFieldToJson(*field, report, provenance, hash).dump());
        } catch (const std::exception&) {
        }
    }
    std::lock_guard<std::mutex> lock(mutex_);
    memory_.emplace(hash, std::move(field));
}

}  // namespace isotrace::geometry
