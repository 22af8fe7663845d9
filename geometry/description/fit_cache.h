// Fits of variational and MPU fields kept by the content hash of what they
// were fitted to: in memory for the cache's life and, given a folder, on disk
// across runs. The host chooses the folder; the library reads no
// environment variable and keeps no process-wide state.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "geometry/description/json_reader.h"
#include "geometry/fields/vdb_level_set.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/variational/rbf_solver.h"

namespace isotrace::geometry {

class FitCache {
public:
    /// `directory` empty: memory only.
    explicit FitCache(std::string directory = "") : directory_(std::move(directory)) {}

    const std::string& directory() const { return directory_; }
    /// The fit stored under `hash`, from memory or disk; null when there is
    /// none (a damaged disk entry counts as none, and is rewritten later).
    std::shared_ptr<const VariationalField> find(const std::string& hash);
    /// Keeps a fit. Writing it to disk may fail (a read-only folder): the
    /// cache is an optimisation, so that is no error.
    void store(const std::string& hash, std::shared_ptr<const VariationalField> field, const FitReport& report,
               const Json& provenance);

    /// The same for MPU fits (their hashes are of points and options).
    std::shared_ptr<const MpuField> findMpu(const std::string& hash);
    void storeMpu(const std::string& hash, std::shared_ptr<const MpuField> field, const MpuReport& report,
                  const Json& provenance);

    /// Level sets read from VDB files, in memory only, by file, grid and
    /// the file's size and time (a scene naming one file twice reads it once).
    std::shared_ptr<const VdbLevelSet> findLevelSet(const std::string& key);
    void storeLevelSet(const std::string& key, std::shared_ptr<const VdbLevelSet> levelSet);

private:
    template <class Field, class Parse>
    std::shared_ptr<const Field> findIn(std::map<std::string, std::shared_ptr<const Field>>& memory, const char* kind,
                                        const std::string& hash, Parse&& parse);
    void writeEntry(const char* kind, const std::string& hash, const Json& entry) const;
    std::string pathOf(const char* kind, const std::string& hash) const;

    std::string directory_;
    std::mutex mutex_;
    std::map<std::string, std::shared_ptr<const VariationalField>> memory_;
    std::map<std::string, std::shared_ptr<const MpuField>> mpuMemory_;
    std::map<std::string, std::shared_ptr<const VdbLevelSet>> levelSets_;
};

}  // namespace isotrace::geometry
