// The "variational" field description of scene files (docs/scene-format.md):
// constraints inline, from an oriented point set or a polygon model, fitted
// on load and cached by content hash; or the saved output of `isotrace fit`.
#pragma once

#include <memory>
#include <string>

#include "geometry/json_reader.h"
#include "rbf_solver.h"

namespace isotrace::geometry {

/// Constraints read from a description, with what they came from.
struct VariationalSource {
    ConstraintSet constraints;
    FitOptions options;
    Json provenance;       ///< the description with file names resolved and their hashes
    std::string hash;      ///< of the description and the bytes of every file it names
};

/// Reads the constraint keys of `r` (all but "fitted"); file names are
/// relative to `baseDirectory`. Errors are InputErrors at the key.
VariationalSource readVariationalSource(JsonObjectReader& r, const std::string& baseDirectory);

/// The field of a description: loaded from "fitted", or fitted (and cached
/// in memory and in variationalCacheDirectory()). Fit errors become
/// InputErrors at the description; fit warnings go to stderr.
std::shared_ptr<const VariationalField> variationalFieldFromDescription(JsonObjectReader& r,
                                                                         const std::string& baseDirectory);

/// The saved form of a fitted field: every number round-trips exactly, so a
/// loaded field evaluates bit-identically to the fitted one.
Json variationalFieldToJson(const VariationalField& field, const FitReport& report, const Json& provenance,
                            const std::string& hash);
/// Reads the saved form; malformed content throws InputError naming `file`.
VariationalField variationalFieldFromJson(const Json& json, const std::string& file);

/// $ISOTRACE_CACHE_DIR, else $XDG_CACHE_HOME/isotrace, else ~/.cache/isotrace.
std::string variationalCacheDirectory();

}  // namespace isotrace::geometry
