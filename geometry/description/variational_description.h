// The "variational" field description of scene files (docs/scene-format.md):
// constraints inline, from an oriented point set or a polygon model, fitted
// on load and cached by content hash; or the saved output of `isotrace fit`.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "geometry/field_program.h"
#include "geometry/description/fit_cache.h"
#include "geometry/description/json_reader.h"
#include "geometry/pointsets/variational_partition.h"
#include "geometry/variational/rbf_solver.h"

namespace isotrace::geometry {

/// How a description's constraints are fitted: "solver" in scene files.
enum class VariationalSolver {
    Automatic,  ///< dense up to FitOptions::maxUnknowns, partitioned beyond
    Dense,      ///< one global interpolant (rbf_solver.h)
    Partition,  ///< local interpolants blended (pointsets/variational_partition.h)
};

/// Constraints read from a description, with what they came from.
struct VariationalSource {
    ConstraintSet constraints;
    FitOptions options;
    VariationalSolver solver = VariationalSolver::Automatic;
    Json provenance;       ///< where the constraints came from (files with their hashes, counts)
    std::string hash;      ///< of the constraints and fit options themselves: the cache key

    /// The partitioned solver's options for this source (its domain margin).
    PartitionOptions partitionOptions() const {
        PartitionOptions o;
        o.domainMargin = options.domainMargin;
        return o;
    }

    bool partitioned() const {
        return solver == VariationalSolver::Partition ||
               (solver == VariationalSolver::Automatic && constraints.unknowns() > options.maxUnknowns);
    }
};

/// A fitted variational field: one global interpolant, or a partition of
/// local ones (an MpuField whose locals are interpolants).
struct VariationalFit {
    std::shared_ptr<const VariationalField> dense;
    std::shared_ptr<const MpuField> partition;
};

/// The other fields of the library a description sits in: "sample" compiles
/// one, "blend" names some. The field parser's compiler is one.
class FieldReferences {
public:
    virtual ~FieldReferences() = default;
    /// Compiles a field (a name or a description at `pointer`).
    virtual FieldProgram compileField(const Json& field, const std::string& pointer) = 0;
    /// The description a name stands for, and its pointer; throws
    /// InputError for unknown names.
    virtual std::pair<const Json*, std::string> describe(const std::string& name, const std::string& pointer) = 0;
};

/// What a description may refer to beyond files.
struct VariationalContext {
    std::string baseDirectory;  ///< file names are relative to it
    /// Null where a description stands alone (`isotrace fit`).
    FieldReferences* references = nullptr;
    std::vector<std::string> blendStack;  ///< names being blended, to report cycles
    /// Where fits are looked up and kept (by default: this context's own
    /// memory).
    std::shared_ptr<FitCache> fits = std::make_shared<FitCache>();
    /// Told of fits that succeed with a warning (ill-conditioned systems):
    /// the file, the JSON pointer and the message. Empty: dropped.
    std::function<void(const std::string& file, const std::string& pointer, const std::string& message)> warn;
};

/// A file name of a description: relative names are relative to the
/// context's base directory (the scene file's).
std::string resolvedFileName(const std::string& name, const std::string& baseDirectory);

/// Oriented points from "points" (a point set file), "mesh" (a polygon
/// model, welded), "sample" with "count" (particles on another field) and
/// "normals" (inline rows), in that order; provenance records the files.
std::vector<OrientedPoint> readOrientedPointSources(JsonObjectReader& r, VariationalContext& context, Json& provenance);

/// Reads the constraint keys of `r` (all but "fitted"). Errors are
/// InputErrors at the key.
VariationalSource readVariationalSource(JsonObjectReader& r, VariationalContext& context);

/// The fit of a source, from the context's cache or the solver (then
/// cached). Fit errors become InputErrors at `r`'s pointer.
std::shared_ptr<const VariationalField> fitCached(const VariationalSource& source, const JsonObjectReader& r,
                                                  const VariationalContext& context);

/// The partitioned fit of a source, likewise cached.
std::shared_ptr<const MpuField> fitPartitionCached(const VariationalSource& source, const JsonObjectReader& r,
                                                   const VariationalContext& context);

/// The field of a description: loaded from "fitted" (either saved form), or
/// fitted by the solver it asks for (and kept in the context's cache). Fit
/// warnings go to the context's `warn`.
VariationalFit variationalFitFromDescription(JsonObjectReader& r, VariationalContext& context);

/// The common head of saved fits (variational and MPU): checks the format
/// key and version, reads past "source", "fit" and "source_hash", and
/// returns the reader for the rest. `what` and `howToWrite` name the kind
/// in errors ("a fitted MPU field", "isotrace fit --method mpu").
JsonObjectReader openSavedFit(const Json& json, const std::string& file, const char* formatKey, int version,
                              const char* what, const char* howToWrite);
/// A saved fit's "domain": a finite, non-empty box.
Box3 readSavedDomain(JsonObjectReader& r);
Json vec3Json(const Vec3& v);

/// The saved form of a fitted field: every number round-trips exactly, so a
/// loaded field evaluates bit-identically to the fitted one.
Json variationalFieldToJson(const VariationalField& field, const FitReport& report, const Json& provenance,
                            const std::string& hash);
/// Reads the saved form; malformed content throws InputError naming `file`.
VariationalField variationalFieldFromJson(const Json& json, const std::string& file);

}  // namespace isotrace::geometry
