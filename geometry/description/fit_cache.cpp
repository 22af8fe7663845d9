#include "geometry/description/fit_cache.h"

#include <filesystem>

#include "geometry/atomic_file.h"
#include "geometry/description/mpu_description.h"
#include "geometry/description/variational_description.h"

namespace isotrace::geometry {

std::string FitCache::pathOf(const char* kind, const std::string& hash) const {
    return directory_.empty() ? "" : (std::filesystem::path(directory_) / (std::string(kind) + "-" + hash + ".json")).string();
}

template <class Field, class Parse>
std::shared_ptr<const Field> FitCache::findIn(std::map<std::string, std::shared_ptr<const Field>>& memory,
                                              const char* kind, const std::string& hash, Parse&& parse) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (auto it = memory.find(hash); it != memory.end()) return it->second;
    }
    const std::string path = pathOf(kind, hash);
    if (path.empty() || !std::filesystem::exists(path)) return nullptr;
    std::shared_ptr<const Field> field;
    try {
        const Json j = parseJsonFile(path);
        if (j.value("source_hash", "") == hash) field = std::make_shared<const Field>(parse(j, path));
    } catch (const std::exception&) {
        return nullptr;  // a damaged entry is refitted and rewritten
    }
    if (field) {
        std::lock_guard<std::mutex> lock(mutex_);
        memory.emplace(hash, field);
    }
    return field;
}

void FitCache::writeEntry(const char* kind, const std::string& hash, const Json& entry) const {
    if (const std::string path = pathOf(kind, hash); !path.empty()) {
        try {
            std::filesystem::create_directories(std::filesystem::path(path).parent_path());
            writeFileAtomically(path, entry.dump());
        } catch (const std::exception&) {
        }
    }
}

std::shared_ptr<const VariationalField> FitCache::find(const std::string& hash) {
    return findIn(memory_, "variational", hash, variationalFieldFromJson);
}

void FitCache::store(const std::string& hash, std::shared_ptr<const VariationalField> field, const FitReport& report,
                     const Json& provenance) {
    writeEntry("variational", hash, variationalFieldToJson(*field, report, provenance, hash));
    std::lock_guard<std::mutex> lock(mutex_);
    memory_.emplace(hash, std::move(field));
}

std::shared_ptr<const MpuField> FitCache::findMpu(const std::string& hash) {
    return findIn(mpuMemory_, "mpu", hash, mpuFieldFromJson);
}

void FitCache::storeMpu(const std::string& hash, std::shared_ptr<const MpuField> field, const MpuReport& report,
                        const Json& provenance) {
    writeEntry("mpu", hash, mpuFieldToJson(*field, report, provenance, hash));
    std::lock_guard<std::mutex> lock(mutex_);
    mpuMemory_.emplace(hash, std::move(field));
}

std::shared_ptr<const VdbLevelSet> FitCache::findLevelSet(const std::string& key) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = levelSets_.find(key);
    return it == levelSets_.end() ? nullptr : it->second;
}

void FitCache::storeLevelSet(const std::string& key, std::shared_ptr<const VdbLevelSet> levelSet) {
    std::lock_guard<std::mutex> lock(mutex_);
    levelSets_.emplace(key, std::move(levelSet));
}

}  // namespace isotrace::geometry
