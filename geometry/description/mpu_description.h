// The JSON of MPU fields: {"type": "mpu", "points" | "mesh" | "sample" |
// "normals": ..., "accuracy", "support", "max_depth", "min_points",
// "sharp_features"}, or {"type": "mpu", "fitted": FILE} for the saved output
// of `isotrace fit --method mpu`.
#pragma once

#include <memory>

#include "geometry/description/variational_description.h"
#include "geometry/pointsets/mpu_field.h"
#include "geometry/pointsets/variational_partition.h"

namespace isotrace::geometry {

/// The key that marks a saved MPU fit (partitioned variational fits too).
inline constexpr const char* kMpuFitFormatKey = "isotrace_mpu_fit";

/// Oriented points and fit options read from a description.
struct MpuSource {
    std::vector<MpuPoint> points;
    MpuOptions options;
    Json provenance;   ///< where the points came from, and the options
    std::string hash;  ///< of the points and options: the cache key
};

/// Reads the point and option keys of `r` (all but "fitted"). Errors are
/// InputErrors at the key.
MpuSource readMpuSource(JsonObjectReader& r, VariationalContext& context);

/// Fits a source. Bad points become InputErrors at `r`'s pointer, a fit
/// that misses its accuracy a warning through `warn` (if set).
MpuField fitMpuSource(const MpuSource& source, const JsonObjectReader& r, MpuReport& report,
                      const std::function<void(const std::string&)>& warn);

/// Fits (or finds in the context's cache, by the points' content and the
/// options) the MPU field a description asks for, or loads its "fitted"
/// file. Errors are InputErrors at the key.
std::shared_ptr<const MpuField> mpuFieldFromDescription(JsonObjectReader& r, VariationalContext& context);

/// The saved form of a fit: every number round-trips exactly, so a loaded
/// field evaluates bit-identically to the fitted one.
/// A partitioned variational fit's report in the saved MPU form's terms
/// (local functions, depth, max error = the largest residual, seconds).
MpuReport partitionSummary(const PartitionReport& report);

Json mpuFieldToJson(const MpuField& field, const MpuReport& report, const Json& provenance, const std::string& hash);
/// Reads the saved form; malformed content throws InputError naming `file`
/// and the place in it.
MpuField mpuFieldFromJson(const Json& json, const std::string& file);

}  // namespace isotrace::geometry
