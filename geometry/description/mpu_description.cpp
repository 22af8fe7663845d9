#include "geometry/description/mpu_description.h"

#include <map>
#include <mutex>

#include "geometry/content_hash.h"

namespace isotrace::geometry {

namespace {

// Fits kept for the process, by content: a scene that shows one scan twice,
// or is loaded again, fits it once.
std::shared_ptr<const MpuField> cachedFit(const std::string& key, const std::function<MpuField()>& fit) {
    static std::mutex mutex;
    static std::map<std::string, std::shared_ptr<const MpuField>> fits;
    {
        std::lock_guard<std::mutex> lock(mutex);
        if (const auto it = fits.find(key); it != fits.end()) return it->second;
    }
    auto field = std::make_shared<const MpuField>(fit());
    std::lock_guard<std::mutex> lock(mutex);
    return fits.emplace(key, std::move(field)).first->second;
}

}  // namespace

std::shared_ptr<const MpuField> mpuFieldFromDescription(JsonObjectReader& r, VariationalContext& context) {
    Json provenance = Json::object();
    const std::vector<OrientedPoint> oriented = readOrientedPointSources(r, context, provenance);
    MpuOptions options;
    options.accuracy = r.number("accuracy", options.accuracy);
    if (!(options.accuracy > 0 && options.accuracy < 1)) r.fail("accuracy", "must lie in (0, 1) (relative to the points' size)");
    options.support = r.number("support", options.support);
    if (!(options.support > 0.5 && options.support <= 4)) r.fail("support", "must lie in (0.5, 4]");
    options.maxDepth = int(r.integer("max_depth", options.maxDepth, 1, 20));
    options.minPoints = int(r.integer("min_points", options.minPoints, 6, 1000));
    if (oriented.empty())
        r.failHere("an MPU field needs oriented points: \"points\", \"mesh\", \"sample\" or \"normals\"");
    r.finish();  // a misspelt key fails before the fit
    std::vector<MpuPoint> points;
    points.reserve(oriented.size());
    for (const OrientedPoint& p : oriented) points.push_back({p.position, p.normal});
    uint64_t h = fnv1a64("mpu 1");
    h = fnv1a64(std::string_view(reinterpret_cast<const char*>(points.data()), points.size() * sizeof(MpuPoint)), h);
    h = fnv1a64(std::string_view(reinterpret_cast<const char*>(&options), sizeof options), h);
    try {
        return cachedFit(hexDigest(h), [&] {
            MpuReport report;
            MpuField field = MpuField::fit(points, options, &report);
            if (context.warn && report.maxError > 3 * options.accuracy)
                context.warn(r.file(), r.pointer(),
                             "the fit misses some points by " + std::to_string(report.maxError) +
                                 " of the points' size (accuracy " + std::to_string(options.accuracy) +
                                 "): too few points where the surface bends or folds");
            return field;
        });
    } catch (const std::invalid_argument& e) {
        throw InputError(r.file(), r.pointer(), e.what());
    }
}

}  // namespace isotrace::geometry
