#include "geometry/description/mpu_description.h"

#include <array>
#include <cstring>
#include <map>

#include "geometry/content_hash.h"

namespace isotrace::geometry {

namespace {

constexpr const char* kFormatKey = kMpuFitFormatKey;
constexpr int kFormatVersion = 1;
// Part of the cache key: bump when the fit's result changes for the same
// points and options, so stale cache entries are not reused.
constexpr const char* kFitRevision = "mpu 4 grown balls trimmed";

constexpr std::array<std::pair<MpuCombination, const char*>, 6> kCombinationNames{{
    {MpuCombination::Single, "single"},
    {MpuCombination::Max, "max"},
    {MpuCombination::Min, "min"},
    {MpuCombination::MaxOfMin, "max_of_min"},
    {MpuCombination::MinOfMax, "min_of_max"},
    {MpuCombination::Interpolant, "interpolant"},
}};

// The options as the fit uses them, field by field (hashing the struct's
// bytes would hash its padding too).
uint64_t hashOptions(const MpuOptions& o, uint64_t h) {
    auto add = [&](const auto& value) {
        h = fnv1a64(std::string_view(reinterpret_cast<const char*>(&value), sizeof value), h);
    };
    add(o.accuracy);
    add(o.support);
    add(o.maxDepth);
    add(o.minPoints);
    add(o.sharpFeatures);
    return h;
}

}  // namespace

MpuSource readMpuSource(JsonObjectReader& r, VariationalContext& context) {
    MpuSource source;
    source.provenance = Json::object();
    const std::vector<OrientedPoint> oriented = readOrientedPointSources(r, context, source.provenance);
    MpuOptions& options = source.options;
    options.accuracy = r.number("accuracy", options.accuracy);
    if (!(options.accuracy > 0 && options.accuracy < 1)) r.fail("accuracy", "must lie in (0, 1) (relative to the points' size)");
    options.support = r.number("support", options.support);
    if (!(options.support > 0.5 && options.support <= 4)) r.fail("support", "must lie in (0.5, 4]");
    options.maxDepth = int(r.integer("max_depth", options.maxDepth, 1, 20));
    options.minPoints = int(r.integer("min_points", options.minPoints, 6, 1000));
    options.sharpFeatures = r.boolean("sharp_features", options.sharpFeatures);
    if (oriented.empty())
        r.failHere("an MPU field needs oriented points: \"points\", \"mesh\", \"sample\" or \"normals\" (or \"fitted\")");
    source.points.reserve(oriented.size());
    for (const OrientedPoint& p : oriented) source.points.push_back({p.position, p.normal});
    source.provenance["accuracy"] = options.accuracy;
    source.provenance["support"] = options.support;
    source.provenance["max_depth"] = options.maxDepth;
    source.provenance["min_points"] = options.minPoints;
    source.provenance["sharp_features"] = options.sharpFeatures;
    uint64_t h = fnv1a64(kFitRevision);
    for (const MpuPoint& p : source.points)
        for (const Vec3* v : {&p.position, &p.normal})
            h = fnv1a64(std::string_view(reinterpret_cast<const char*>(v->data()), 3 * sizeof(double)), h);
    source.hash = hexDigest(hashOptions(options, h));
    return source;
}

MpuField fitMpuSource(const MpuSource& source, const JsonObjectReader& r, MpuReport& report,
                      const std::function<void(const std::string&)>& warn) {
    MpuField field;
    try {
        field = MpuField::fit(source.points, source.options, &report);
    } catch (const std::invalid_argument& e) {
        throw InputError(r.file(), r.pointer(), e.what());
    }
    if (warn && report.maxError > 3 * source.options.accuracy)
        warn("the fit misses some points by " + std::to_string(report.maxError) + " of the points' size (accuracy " +
             std::to_string(source.options.accuracy) + "): too few points where the surface bends or folds" +
             (source.options.minPoints > 6 ? " (a smaller min_points, down to 6, lets cells there divide further)" : ""));
    return field;
}

std::shared_ptr<const MpuField> mpuFieldFromDescription(JsonObjectReader& r, VariationalContext& context) {
    if (r.has("fitted")) {
        const std::string path = resolvedFileName(r.string("fitted"), context.baseDirectory);
        r.finish();  // a misspelt key fails before any file is read
        try {
            return std::make_shared<const MpuField>(mpuFieldFromJson(parseJsonFile(path), path));
        } catch (const InputError& e) {
            throw InputError(r.file(), r.pointerOf("fitted"), e.what());
        }
    }
    const MpuSource source = readMpuSource(r, context);
    r.finish();  // a misspelt key fails before the fit
    if (std::shared_ptr<const MpuField> field = context.fits->findMpu(source.hash)) return field;
    MpuReport report;
    auto field = std::make_shared<const MpuField>(fitMpuSource(source, r, report, [&](const std::string& message) {
        if (context.warn) context.warn(r.file(), r.pointer(), message);
    }));
    context.fits->storeMpu(source.hash, field, report, source.provenance);
    return field;
}

MpuReport partitionSummary(const PartitionReport& report) {
    MpuReport summary;
    summary.localFunctions = report.locals;
    summary.depth = report.depth;
    summary.maxError = report.maxResidual;
    summary.seconds = report.seconds;
    return summary;
}

namespace {

// Vectors as one flat array [x0, y0, z0, x1, ...].
Json flat(const std::vector<Vec3>& vectors) {
    std::vector<double> out;
    out.reserve(3 * vectors.size());
    for (const Vec3& v : vectors) out.insert(out.end(), {v.x(), v.y(), v.z()});
    return out;
}

// Interpolants share their centres (each constraint is in about a dozen
// balls): the saved form lists each position once and refers to it by index.
class PositionTable {
public:
    uint32_t indexOf(const Vec3& p) {
        const auto [it, added] = index_.try_emplace(key(p), uint32_t(positions_.size()));
        if (added) positions_.push_back(p);
        return it->second;
    }
    const std::vector<Vec3>& positions() const { return positions_; }

private:
    static std::array<uint64_t, 3> key(const Vec3& p) {
        std::array<uint64_t, 3> k;
        std::memcpy(k.data(), p.data(), sizeof k);
        return k;
    }
    std::map<std::array<uint64_t, 3>, uint32_t> index_;
    std::vector<Vec3> positions_;
};

}  // namespace

Json mpuFieldToJson(const MpuField& field, const MpuReport& report, const Json& provenance, const std::string& hash) {
    Json locals = Json::array(), pieces = Json::array();
    for (const MpuLocal& l : field.locals()) {
        const char* name = "single";
        for (const auto& [c, n] : kCombinationNames)
            if (c == l.combination) name = n;
        locals.push_back({l.center.x(), l.center.y(), l.center.z(), l.radius, l.first, l.count, name});
    }
    for (const MpuQuadric& q : field.pieces())
        pieces.push_back({q.origin.x(), q.origin.y(), q.origin.z(), q.A(0, 0), q.A(0, 1), q.A(0, 2), q.A(1, 1), q.A(1, 2),
                          q.A(2, 2), q.g.x(), q.g.y(), q.g.z(), q.c0});
    Json out = {{kFormatKey, kFormatVersion},
            {"source", provenance},
            {"source_hash", hash},
            {"fit",
             {{"local_functions", report.localFunctions},
              {"general_quadrics", report.generalQuadrics},
              {"edges", report.edges},
              {"corners", report.corners},
              {"depth", report.depth},
              {"max_error", report.maxError},
              {"mean_error", report.meanError},
              {"seconds", report.seconds}}},
            {"domain", Json::array({vec3Json(field.bounds().lower), vec3Json(field.bounds().upper)})},
            {"support", field.support()},
            {"background_margin", field.backgroundMargin()},
            {"locals", locals},
            {"pieces", pieces}};
    if (field.hasInterpolants()) {
        Json interpolants = Json::array();
        PositionTable table;
        auto indices = [&](const auto& centers) {
            std::vector<uint32_t> out;
            for (const Vec3& c : centers) out.push_back(table.indexOf(c));
            return out;
        };
        for (const VariationalField& f : field.interpolants())
            interpolants.push_back({{"constant", f.constant},
                                    {"linear", vec3Json(f.linear)},
                                    {"centers", indices(f.centers)},
                                    {"weights", f.weights},
                                    {"gradient_centers", indices(f.gradientCenters)},
                                    {"gradient_weights", flat(f.gradientWeights)}});
        out["positions"] = flat(table.positions());
        out["interpolants"] = std::move(interpolants);
    }
    return out;
}

MpuField mpuFieldFromJson(const Json& json, const std::string& file) {
    JsonObjectReader r =
        openSavedFit(json, file, kFormatKey, kFormatVersion, "a fitted MPU field", "isotrace fit --method mpu");
    const Box3 domain = readSavedDomain(r);
    const double support = r.number("support");
    const double backgroundMargin = r.number("background_margin");
    // Rows of numbers, with the row's pointer for errors.
    auto rowsOf = [&](const char* key, size_t width, const char* shape, auto&& read) {
        const Json& a = r.value(key);
        if (!a.is_array()) r.fail(key, std::string("expected an array of ") + shape);
        for (size_t i = 0; i < a.size(); ++i) {
            const std::string at = jsonPointerAppend(r.pointerOf(key), i);
            const Json& row = a[i];
            if (!row.is_array() || row.size() != width) throw InputError(file, at, std::string("expected ") + shape);
            read(row, at);
        }
    };
    auto number = [&](const Json& v, const std::string& at) {
        if (!v.is_number() || !std::isfinite(v.get<double>())) throw InputError(file, at, "expected a finite number");
        return v.get<double>();
    };
    std::vector<MpuLocal> locals;
    rowsOf("locals", 7, "[x, y, z, radius, first piece, pieces, combination]", [&](const Json& row, const std::string& at) {
        MpuLocal l;
        l.center = Vec3(number(row[0], at + "/0"), number(row[1], at + "/1"), number(row[2], at + "/2"));
        l.radius = number(row[3], at + "/3");
        auto integer = [&](const Json& v, int64_t lo, int64_t hi) {
            return v.is_number_integer() && v.get<int64_t>() >= lo && v.get<int64_t>() <= hi;
        };
        if (!integer(row[4], 0, UINT32_MAX)) throw InputError(file, at + "/4", "expected the index of a piece");
        if (!integer(row[5], 1, 3)) throw InputError(file, at + "/5", "expected 1, 2 or 3 pieces");
        l.first = uint32_t(row[4].get<int64_t>());
        l.count = uint8_t(row[5].get<int64_t>());
        bool known = false;
        if (row[6].is_string())
            for (const auto& [c, n] : kCombinationNames)
                if (row[6].get<std::string>() == n) l.combination = c, known = true;
        if (!known) throw InputError(file, at + "/6", "expected single, max, min, max_of_min, min_of_max or interpolant");
        locals.push_back(l);
    });
    std::vector<MpuQuadric> pieces;
    rowsOf("pieces", 13, "[origin (3), A00, A01, A02, A11, A12, A22, g (3), c0]", [&](const Json& row, const std::string& at) {
        double v[13];
        for (int k = 0; k < 13; ++k) v[k] = number(row[k], at + "/" + std::to_string(k));
        MpuQuadric q;
        q.origin = Vec3(v[0], v[1], v[2]);
        q.A << v[3], v[4], v[5], v[4], v[6], v[7], v[5], v[7], v[8];
        q.g = Vec3(v[9], v[10], v[11]);
        q.c0 = v[12];
        pieces.push_back(q);
    });
    std::vector<VariationalField> interpolants;
    std::vector<Vec3> positions;
    if (r.has("positions")) {
        const std::vector<double> v = r.numbers("positions");
        if (v.size() % 3 != 0) r.fail("positions", "expected a flat array of [x, y, z] triples");
        for (size_t k = 0; k + 2 < v.size(); k += 3) positions.emplace_back(v[k], v[k + 1], v[k + 2]);
    }
    if (const Json* list = r.optionalValue("interpolants")) {
        const std::string pointer = r.pointerOf("interpolants");
        if (!list->is_array()) throw InputError(file, pointer, "expected an array of interpolants");
        for (size_t i = 0; i < list->size(); ++i) {
            JsonObjectReader f((*list)[i], jsonPointerAppend(pointer, i), file);
            VariationalField field;
            field.constant = f.number("constant");
            field.linear = f.vec3("linear");
            auto positionsAt = [&](const char* key) {
                const Json& a = f.value(key);
                if (!a.is_array()) f.fail(key, "expected an array of indices into \"positions\"");
                std::vector<Vec3> out;
                out.reserve(a.size());
                for (size_t k = 0; k < a.size(); ++k) {
                    if (!a[k].is_number_unsigned() || a[k].get<uint64_t>() >= positions.size())
                        throw InputError(file, jsonPointerAppend(f.pointerOf(key), k),
                                         "expected an index into \"positions\" (" + std::to_string(positions.size()) +
                                             " of them)");
                    out.push_back(positions[a[k].get<uint64_t>()]);
                }
                return out;
            };
            field.centers = positionsAt("centers");
            field.weights = f.numbers("weights");
            field.gradientCenters = positionsAt("gradient_centers");
            const std::vector<double> g = f.numbers("gradient_weights");
            if (g.size() % 3 != 0) f.fail("gradient_weights", "expected a flat array of [x, y, z] triples");
            for (size_t k = 0; k + 2 < g.size(); k += 3) field.gradientWeights.emplace_back(g[k], g[k + 1], g[k + 2]);
            if (field.weights.size() != field.centers.size()) f.fail("weights", "one weight per center expected");
            if (field.gradientWeights.size() != field.gradientCenters.size())
                f.fail("gradient_weights", "one weight vector per gradient center expected");
            f.finish();
            interpolants.push_back(std::move(field));
        }
    }
    r.finish();
    try {
        return MpuField::fromParts(domain, support, backgroundMargin, std::move(locals), std::move(pieces),
                                   std::move(interpolants));
    } catch (const std::invalid_argument& e) {
        throw InputError(file, "", e.what());
    }
}

}  // namespace isotrace::geometry
