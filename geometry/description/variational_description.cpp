#include "geometry/description/variational_description.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "geometry/content_hash.h"
#include "geometry/description/mpu_description.h"
#include "geometry/mesh_file.h"
#include "geometry/particles/surface_particles.h"
#include "geometry/pointsets/variational_partition.h"

namespace isotrace::geometry {

namespace {

constexpr const char* kFormatKey = "isotrace_variational_fit";
constexpr int kFormatVersion = 1;
// Part of the cache key: bump when the fit's result changes for the same
// input (solver, domain choice), so stale cache entries are not reused.
constexpr const char* kFitRevision = "r3-qr-llt-2";
// The same for partitioned fits (combined with the constraints' hash).
constexpr const char* kPartitionRevision = "partition-1";

// An array of rows of `width` finite numbers.
std::vector<std::vector<double>> rows(JsonObjectReader& r, const std::string& key, size_t width, const char* shape) {
    std::vector<std::vector<double>> out;
    const Json* j = r.optionalValue(key);
    if (!j) return out;
    const std::string pointer = r.pointerOf(key);
    if (!j->is_array()) throw InputError(r.file(), pointer, std::string("expected an array of ") + shape);
    for (size_t i = 0; i < j->size(); ++i) {
        const Json& row = (*j)[i];
        const std::string at = jsonPointerAppend(pointer, i);
        if (!row.is_array() || row.size() != width) throw InputError(r.file(), at, std::string("expected ") + shape);
        std::vector<double> v;
        for (size_t k = 0; k < width; ++k) {
            if (!row[k].is_number() || !std::isfinite(row[k].get<double>()))
                throw InputError(r.file(), jsonPointerAppend(at, k), "expected a finite number");
            v.push_back(row[k].get<double>());
        }
        out.push_back(std::move(v));
    }
    return out;
}

Vec3 vec(const std::vector<double>& v, size_t first) { return {v[first], v[first + 1], v[first + 2]}; }


}  // namespace

namespace {

// Oriented points on the surface of any field: particles spread evenly over
// it (every component gets its share), with the field's gradient directions
// as normals. Even spacing keeps constraints apart, which keeps the
// interpolation system well conditioned.
std::vector<OrientedPoint> samplesOf(const FieldProgram& field, int count, JsonObjectReader& r) {
    ParticleOptions options;
    options.count = size_t(count);
    options.seed = 1;
    ParticleSampling sampling;
    try {
        sampling = spreadParticles(field, options);
    } catch (const std::invalid_argument& e) {
        r.fail("sample", e.what());
    }
    std::vector<OrientedPoint> points;
    for (const SurfaceParticle& p : sampling.particles) points.push_back({p.position, p.normal});
    return points;
}

// The cache key: every number the fit sees, the options and the revision.
std::string constraintHash(const ConstraintSet& c, const FitOptions& options) {
    uint64_t h = fnv1a64(kFitRevision);
    auto add = [&](const void* data, size_t bytes) { h = fnv1a64(std::string_view(static_cast<const char*>(data), bytes), h); };
    for (const ValueConstraint& v : c.values) add(&v, sizeof v);
    for (const GradientConstraint& g : c.gradients) add(&g, sizeof g);
    add(&options.domainMargin, sizeof options.domainMargin);
    add(&options.maxUnknowns, sizeof options.maxUnknowns);
    return hexDigest(h);
}

std::vector<OrientedPoint> pointsFromFile(JsonObjectReader& r, const char* key, const VariationalContext& context,
                                          Json& provenance, bool mesh) {
    const std::string name = r.string(key), path = resolvedFileName(name, context.baseDirectory);
    std::vector<OrientedPoint> points;
    MeshRepair repair;
    try {
        if (mesh) {
            // Models repeat vertices at seams: one constraint per place, or
            // the system has two equal rows.
            IndexedMesh m = readMeshFile(path);
            repair = weldCoincidentVertices(m);
            if (m.triangles.empty()) throw InputError(path, "", "every triangle is degenerate");
            points = orientedPointsOfMesh(m);
            checkPointsOutlineASolid(points, path);
        } else {
            points = readOrientedPoints(path);
        }
    } catch (const InputError& e) {
        throw InputError(r.file(), r.pointerOf(key), e.what());
    }
    uint64_t fileHash = kFnvOffsetBasis;
    fnv1a64File(path, fileHash);
    provenance[key] = {{"file", name}, {"hash", hexDigest(fileHash)}, {"count", points.size()}};
    if (repair.weldedVertices || repair.droppedTriangles) {
        provenance[key]["welded_vertices"] = repair.weldedVertices;
        provenance[key]["dropped_triangles"] = repair.droppedTriangles;
        if (context.warn)
            context.warn(r.file(), r.pointerOf(key),
                         "welded " + std::to_string(repair.weldedVertices) +
                             " vertices that coincide with others and dropped " +
                             std::to_string(repair.droppedTriangles) + " degenerate triangles");
    }
    return points;
}

}  // namespace

std::vector<OrientedPoint> readOrientedPointSources(JsonObjectReader& r, VariationalContext& context, Json& provenance) {
    std::vector<OrientedPoint> oriented;
    if (r.has("points")) oriented = pointsFromFile(r, "points", context, provenance, false);
    if (r.has("mesh")) {
        const std::vector<OrientedPoint> m = pointsFromFile(r, "mesh", context, provenance, true);
        oriented.insert(oriented.end(), m.begin(), m.end());
    }
    if (r.has("sample")) {
        if (!context.references) r.fail("sample", "sampling other fields is not available here");
        const int count = int(r.integer("count", 200, 4, 100000));
        const std::vector<OrientedPoint> s = samplesOf(context.references->compileField(r.value("sample"), r.pointerOf("sample")), count, r);
        oriented.insert(oriented.end(), s.begin(), s.end());
        provenance["sample"] = {{"field", r.value("sample")}, {"count", s.size()}};
    }
    for (const auto& v : rows(r, "normals", 6, "[x, y, z, nx, ny, nz] rows")) {
        const Vec3 n = vec(v, 3);
        if (!(n.norm() > 0)) r.fail("normals", "a normal is the zero vector");
        oriented.push_back({vec(v, 0), n.normalized()});
    }
    return oriented;
}

VariationalSource readVariationalSource(JsonObjectReader& r, VariationalContext& context) {
    VariationalSource source;
    Json provenance = Json::object();
    // Oriented points from files, sampled fields and inline "normals".
    const std::vector<OrientedPoint> oriented = readOrientedPointSources(r, context, provenance);
    const bool hermite = r.boolean("hermite", false);
    ConstraintSet explicitRows;
    for (const auto& v : rows(r, "boundary", 3, "[x, y, z] rows")) explicitRows.addBoundary(vec(v, 0));
    for (const auto& v : rows(r, "interior", 3, "[x, y, z] rows")) explicitRows.addInterior(vec(v, 0));
    for (const auto& v : rows(r, "exterior", 3, "[x, y, z] rows")) explicitRows.addExterior(vec(v, 0));
    for (const auto& v : rows(r, "values", 4, "[x, y, z, value] rows")) explicitRows.values.push_back({vec(v, 0), v[3]});
    for (const auto& v : rows(r, "gradients", 6, "[x, y, z, gx, gy, gz] rows"))
        explicitRows.gradients.push_back({vec(v, 0), vec(v, 3)});
    // The default offset scales with everything constrained, so a single
    // oriented point among explicit rows still gets a usable offset.
    double offset = 0;
    if (r.has("normal_offset")) {
        offset = r.positiveNumber("normal_offset");
    } else {
        Box3 box = explicitRows.bounds();
        for (const OrientedPoint& p : oriented) box.extend(p.position);
        offset = oriented.empty() ? 0.0 : 0.01 * box.extent().norm();
        if (!oriented.empty() && !(offset > 0))
            r.fail(r.has("normals") ? "normals" : r.has("points") ? "points" : r.has("mesh") ? "mesh" : "sample",
                   "all constraints lie at one point, so there is no default normal_offset; give one");
    }
    source.constraints = constraintsFromOrientedPoints(oriented, offset, hermite);

    ConstraintSet& c = source.constraints;
    c.values.insert(c.values.end(), explicitRows.values.begin(), explicitRows.values.end());
    c.gradients.insert(c.gradients.end(), explicitRows.gradients.begin(), explicitRows.gradients.end());
    source.options.domainMargin = r.has("margin") ? r.positiveNumber("margin") : source.options.domainMargin;
    if (r.has("solver")) {
        const std::string solver = r.string("solver");
        if (solver == "auto") source.solver = VariationalSolver::Automatic;
        else if (solver == "dense") source.solver = VariationalSolver::Dense;
        else if (solver == "partition") source.solver = VariationalSolver::Partition;
        else r.fail("solver", "unknown solver \"" + solver + "\" (expected \"auto\", \"dense\" or \"partition\")");
    }

    // Blending (Turk and O'Brien 2002, section 6): each operand keeps the
    // constraints that lie outside every other operand; one more fit joins
    // them without the bulge of a function sum.
    if (const Json* blend = r.optionalValue("blend")) {
        const std::string pointer = r.pointerOf("blend");
        if (!blend->is_array() || blend->size() < 2)
            throw InputError(r.file(), pointer, "expected an array of at least two variational fields");
        std::vector<VariationalSource> parts;
        std::vector<std::shared_ptr<const VariationalField>> fields;
        Json partProvenance = Json::array();
        for (size_t i = 0; i < blend->size(); ++i) {
            const Json* description = &(*blend)[i];
            std::string at = jsonPointerAppend(pointer, i);
            bool named = false;
            if (description->is_string()) {
                const std::string name = description->get<std::string>();
                if (std::find(context.blendStack.begin(), context.blendStack.end(), name) != context.blendStack.end())
                    throw InputError(r.file(), at, "cycle in the blend: \"" + name + "\" blends itself");
                if (!context.references) throw InputError(r.file(), at, "named operands are not available here");
                std::tie(description, at) = context.references->describe(name, at);
                context.blendStack.push_back(name);
                named = true;
            }
            JsonObjectReader part(*description, at, r.file());
            if (part.string("type") != "variational")
                part.fail("type", "blend operands must be variational fields");
            parts.push_back(readVariationalSource(part, context));
            part.finish();
            if (named) context.blendStack.pop_back();
            fields.push_back(fitCached(parts.back(), part, context));
            partProvenance.push_back(parts.back().provenance);
        }
        auto outsideOthers = [&](size_t self, const Vec3& p) {
            for (size_t j = 0; j < fields.size(); ++j)
                if (j != self && !(fields[j]->value(p) > 0)) return false;
            return true;
        };
        Json kept = Json::array();
        for (size_t i = 0; i < parts.size(); ++i) {
            size_t n = 0;
            for (const ValueConstraint& v : parts[i].constraints.values)
                if (outsideOthers(i, v.position)) c.values.push_back(v), ++n;
            for (const GradientConstraint& g : parts[i].constraints.gradients)
                if (outsideOthers(i, g.position)) c.gradients.push_back(g), ++n;
            kept.push_back(n);
        }
        provenance["blend"] = {{"operands", partProvenance}, {"kept_constraints", kept}};
    }

    if (c.values.empty() && c.gradients.empty())
        r.failHere("a variational field needs constraints: \"points\", \"mesh\", \"sample\", \"normals\", "
                   "\"boundary\", \"interior\", \"exterior\", \"values\", \"gradients\" or \"blend\" (or \"fitted\")");
    provenance["normal_offset"] = offset;
    provenance["hermite"] = hermite;
    source.provenance = provenance;
    source.hash = constraintHash(c, source.options);
    if (source.partitioned()) {
        source.hash = hexDigest(fnv1a64(kPartitionRevision, fnv1a64(source.hash)));
        provenance["solver"] = "partition";
        source.provenance = provenance;
    }
    return source;
}

std::string resolvedFileName(const std::string& name, const std::string& baseDirectory) {
    const std::filesystem::path p(name);
    return p.is_absolute() || baseDirectory.empty() ? name : (std::filesystem::path(baseDirectory) / p).string();
}

Json variationalFieldToJson(const VariationalField& f, const FitReport& report, const Json& provenance,
                            const std::string& hash) {
    Json centers = Json::array(), gradientCenters = Json::array(), gradientWeights = Json::array();
    for (const Vec3& c : f.centers) centers.push_back(vec3Json(c));
    for (const Vec3& c : f.gradientCenters) gradientCenters.push_back(vec3Json(c));
    for (const Vec3& b : f.gradientWeights) gradientWeights.push_back(vec3Json(b));
    return {{kFormatKey, kFormatVersion},
            {"source", provenance},
            {"source_hash", hash},
            {"fit",
             {{"unknowns", report.unknowns},
              {"seconds", report.seconds},
              {"max_residual", report.maxResidual},
              {"reciprocal_condition", report.reciprocalCondition}}},
            {"domain", Json::array({vec3Json(f.domain.lower), vec3Json(f.domain.upper)})},
            {"constant", f.constant},
            {"linear", vec3Json(f.linear)},
            {"centers", centers},
            {"weights", f.weights},
            {"gradient_centers", gradientCenters},
            {"gradient_weights", gradientWeights}};
}

Json vec3Json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

JsonObjectReader openSavedFit(const Json& json, const std::string& file, const char* formatKey, int version,
                              const char* what, const char* howToWrite) {
    if (!json.is_object() || !json.contains(formatKey))
        throw InputError(file, "", std::string("not ") + what + " (no \"" + formatKey + "\"; write one with " +
                                       howToWrite + ")");
    JsonObjectReader r(json, "", file);
    const long long found = r.integer(formatKey, 0, 1, 1000);
    if (found != version)
        r.fail(formatKey, "format version " + std::to_string(found) + " is not supported (expected " +
                              std::to_string(version) + ")");
    r.value("source");
    r.value("fit");
    r.string("source_hash", "");
    return r;
}

Box3 readSavedDomain(JsonObjectReader& r) {
    const Json& domain = r.value("domain");
    if (!domain.is_array() || domain.size() != 2) r.fail("domain", "expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]");
    const Box3 box(JsonObjectReader::asVec3(domain[0], r.pointerOf("domain") + "/0", r.file()),
                   JsonObjectReader::asVec3(domain[1], r.pointerOf("domain") + "/1", r.file()));
    if (box.isEmpty() || !box.isFinite()) r.fail("domain", "the domain is empty or not finite");
    return box;
}

VariationalField variationalFieldFromJson(const Json& json, const std::string& file) {
    JsonObjectReader r = openSavedFit(json, file, kFormatKey, kFormatVersion, "a fitted variational field", "isotrace fit");
    VariationalField f;
    f.domain = readSavedDomain(r);
    f.constant = r.number("constant");
    f.linear = r.vec3("linear");
    auto points = [&](const char* key) {
        std::vector<Vec3> out;
        const Json& a = r.value(key);
        if (!a.is_array()) r.fail(key, "expected an array of [x, y, z]");
        for (size_t i = 0; i < a.size(); ++i) out.push_back(JsonObjectReader::asVec3(a[i], jsonPointerAppend(r.pointerOf(key), i), file));
        return out;
    };
    f.centers = points("centers");
    f.weights = r.numbers("weights");
    f.gradientCenters = points("gradient_centers");
    f.gradientWeights = points("gradient_weights");
    if (f.weights.size() != f.centers.size())
        r.fail("weights", std::to_string(f.weights.size()) + " weights for " + std::to_string(f.centers.size()) + " centers");
    if (f.gradientWeights.size() != f.gradientCenters.size())
        r.fail("gradient_weights", "one weight vector per gradient center expected");
    for (size_t i = 0; i < f.weights.size(); ++i)
        if (!std::isfinite(f.weights[i])) r.fail("weights", "weight " + std::to_string(i) + " is not finite");
    r.finish();
    return f;
}

std::shared_ptr<const VariationalField> fitCached(const VariationalSource& source, const JsonObjectReader& r,
                                                  const VariationalContext& context) {
    if (source.partitioned())
        throw InputError(r.file(), r.pointer(),
                         "blend operands are fitted by the dense solver, up to " +
                             std::to_string(source.options.maxUnknowns) + " unknowns; this one has " +
                             std::to_string(source.constraints.unknowns()));
    if (std::shared_ptr<const VariationalField> field = context.fits->find(source.hash)) return field;
    FitReport report;
    std::shared_ptr<const VariationalField> field;
    try {
        field = std::make_shared<const VariationalField>(fitVariationalField(source.constraints, &report, source.options));
    } catch (const FitError& e) {
        throw InputError(r.file(), r.pointer(), e.what());
    }
    if (context.warn)
        for (const std::string& w : report.warnings) context.warn(r.file(), r.pointer(), w);
    context.fits->store(source.hash, field, report, source.provenance);
    return field;
}

std::shared_ptr<const MpuField> fitPartitionCached(const VariationalSource& source, const JsonObjectReader& r,
                                                   const VariationalContext& context) {
    if (std::shared_ptr<const MpuField> field = context.fits->findMpu(source.hash)) return field;
    PartitionReport report;
    std::shared_ptr<const MpuField> field;
    try {
        field = std::make_shared<const MpuField>(
            fitPartitionedVariationalField(source.constraints, &report, source.partitionOptions()));
    } catch (const FitError& e) {
        throw InputError(r.file(), r.pointer(), e.what());
    }
    if (context.warn)
        for (const std::string& w : report.warnings) context.warn(r.file(), r.pointer(), w);
    context.fits->storeMpu(source.hash, field, partitionSummary(report), source.provenance);
    return field;
}

VariationalFit variationalFitFromDescription(JsonObjectReader& r, VariationalContext& context) {
    if (r.has("fitted")) {
        const std::string path = resolvedFileName(r.string("fitted"), context.baseDirectory);
        r.finish();  // a misspelt key fails before any file is read
        try {
            const Json json = parseJsonFile(path);
            // `isotrace fit` saves partitioned fits in the MPU form.
            if (json.is_object() && json.contains(kMpuFitFormatKey))
                return {nullptr, std::make_shared<const MpuField>(mpuFieldFromJson(json, path))};
            return {std::make_shared<const VariationalField>(variationalFieldFromJson(json, path)), nullptr};
        } catch (const InputError& e) {
            throw InputError(r.file(), r.pointerOf("fitted"), e.what());
        }
    }
    const VariationalSource source = readVariationalSource(r, context);
    r.finish();  // a misspelt key fails before a possibly long fit
    if (source.partitioned()) return {nullptr, fitPartitionCached(source, r, context)};
    return {fitCached(source, r, context), nullptr};
}

}  // namespace isotrace::geometry
