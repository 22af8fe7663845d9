#include "renderer/scene_loader.h"

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>

#include "geometry/description/field_parser.h"
#include "geometry/description/json_reader.h"
#include "geometry/meshing/polygonizer.h"
#include "geometry/particles/surface_particles.h"
#include "geometry/physical_memory.h"
#include "renderer/field_hosting.h"
#include "renderer/scene_builder.h"
#include "renderer/scene_values.h"

namespace isotrace {

using geometry::InputError;
using geometry::Json;
using geometry::JsonObjectReader;
using geometry::jsonPointerAppend;

namespace {

constexpr int kMaxImageSide = 1 << 16;
// Rays are single precision in Embree, which refuses origins past 1.8e18;
// far before that a float coordinate has no precision left. Positions and
// transforms stay within these bounds so every ray can be represented.
constexpr double kMaxCoordinate = 1e15;
constexpr double kMaxTransformEntry = 1e9;
constexpr double kMaxFilterRadius = 1000.0;  // pixels

void checkRepresentable(JsonObjectReader& r, const std::string& key, const Vec3& v) {
    if (!(v.cwiseAbs().maxCoeff() <= kMaxCoordinate))
        r.fail(key, "coordinates beyond 1e15 cannot be represented by single-precision rays");
}
constexpr int kMaxSamplesPerPixel = 1 << 20;

class SceneLoader {
public:
    SceneLoader(const std::string& path, const SceneOverrides& overrides)
        : path_(path), overrides_(overrides), directory_(std::filesystem::path(path).parent_path()) {}

    std::unique_ptr<Scene> load() { return load(geometry::parseJsonFile(path_)); }

    std::unique_ptr<Scene> load(const Json& root) {
        JsonObjectReader r(root, "", path_);
        builder_.setSourceFile(path_);
        if (r.has("camera")) readCamera(r.object("camera"));
        if (r.has("film")) readFilm(r.object("film"));
        applyOverrides();
        if (r.has("integrator")) readIntegrator(r.object("integrator"));
        if (const Json* fields = r.optionalValue("fields")) {
            geometry::FieldLibraryOptions options;
            options.fitCache = overrides_.fitCache ? overrides_.fitCache : processFitCache();
            // Fit warnings join the scene's, which the host reports.
            options.warn = [this](const std::string&, const std::string& pointer, const std::string& message) {
                builder_.addWarning(pointer + ": " + message);
            };
            fields_ = geometry::FieldLibrary(*fields, "/fields", path_, std::move(options));
            hasFields_ = true;
        }
        // After the fields: textures may be driven by them.
        if (const Json* materials = r.optionalValue("materials")) {
            if (!materials->is_object()) r.fail("materials", "expected an object mapping material names to materials");
            readMaterials(*materials);
        }
        const Json& objects = r.value("objects");
        if (!objects.is_array()) r.fail("objects", "expected an array of objects");
        if (objects.empty()) r.fail("objects", "the scene is empty: add at least one object");
        if (r.has("lights")) readLights(r.value("lights"), r.pointerOf("lights"));
        std::vector<ObjectRequest> requests;
        for (size_t i = 0; i < objects.size(); ++i) requests.push_back(readObject(objects[i], jsonPointerAppend("/objects", i)));
        r.finish();
        // Every field shown compiles (and fits) before any surface, mesh or
        // particles are built: an error in one field costs nothing else.
        for (const ObjectRequest& q : requests)
            if (!q.field.empty()) compileShown(q.field);
        for (ObjectRequest& q : requests) buildObject(q);
        return builder_.build();
    }

private:
    void readCamera(JsonObjectReader c) {
        c.choice("type", {"perspective"}, "perspective");
        CameraSettings cam = builder_.camera();
        cam.from = c.vec3("from", cam.from);
        cam.to = c.vec3("to", cam.to);
        cam.up = c.vec3("up", cam.up);
        checkRepresentable(c, "from", cam.from);
        checkRepresentable(c, "to", cam.to);
        checkRepresentable(c, "up", cam.up);
        cam.verticalFovDegrees = c.number("fov", cam.verticalFovDegrees);
        if (!(cam.verticalFovDegrees > 0 && cam.verticalFovDegrees < 180)) c.fail("fov", "must be between 0 and 180 degrees");
        cam.aperture = c.number("aperture", 0.0);
        if (cam.aperture < 0) c.fail("aperture", "must not be negative");
        if (cam.aperture > kMaxCoordinate) c.fail("aperture", "beyond 1e15 cannot be represented by single-precision rays");
        // 0 stands for the default, the distance from "from" to "to".
        cam.focusDistance = c.has("focus_distance") ? c.positiveNumber("focus_distance") : 0.0;
        if (cam.focusDistance > kMaxCoordinate)
            c.fail("focus_distance", "beyond 1e15 cannot be represented by single-precision rays");
        if (!((cam.to - cam.from).norm() > 0)) c.fail("to", "must differ from \"from\"");
        if (cam.focusDistance == 0) cam.focusDistance = (cam.to - cam.from).norm();
        if (!((cam.to - cam.from).normalized().cross(cam.up).norm() > 1e-9)) c.fail("up", "must not be parallel to the view direction");
        c.finish();
        builder_.setCamera(cam);
    }

    void readFilm(JsonObjectReader f) {
        FilmSettings film = builder_.film();
        film.width = static_cast<int>(f.integer("width", film.width, 1, kMaxImageSide));
        film.height = static_cast<int>(f.integer("height", film.height, 1, kMaxImageSide));
        film.samplesPerPixel = static_cast<int>(f.integer("spp", film.samplesPerPixel, 1, kMaxSamplesPerPixel));
        const std::string sampler = f.choice("sampler", {"sobol", "independent"}, "sobol");
        film.sampler = sampler == "sobol" ? SamplerType::Sobol : SamplerType::Independent;
        if (f.has("filter")) {
            JsonObjectReader filter = f.object("filter");
            const std::string type = filter.choice("type", {"box", "gaussian"}, "");
            film.filter.type = type == "box" ? FilterType::Box : FilterType::Gaussian;
            film.filter.radius = filter.positiveNumber("radius", type == "box" ? 0.5 : 1.5);
            if (film.filter.radius > kMaxFilterRadius) filter.fail("radius", "must be at most 1000 pixels");
            if (film.filter.type == FilterType::Gaussian) film.filter.sigma = filter.positiveNumber("sigma", 0.5);
            if (film.filter.sigma > kMaxFilterRadius) filter.fail("sigma", "must be at most 1000 pixels");
            filter.finish();
        }
        f.finish();
        builder_.setFilm(film);
    }

    void applyOverrides() {
        FilmSettings film = builder_.film();
        if (overrides_.width > 0) film.width = overrides_.width;
        if (overrides_.height > 0) film.height = overrides_.height;
        if (overrides_.samplesPerPixel > 0) film.samplesPerPixel = overrides_.samplesPerPixel;
        const double bytes = estimateFilmBytes(film.width, film.height);
        const double available = geometry::physicalMemoryBytes();
        if (bytes > 0.5 * available)
            throw InputError(path_, "/film", "a " + std::to_string(film.width) + "x" + std::to_string(film.height) +
                                                 " image needs about " + std::to_string(bytes / (1 << 30)) +
                                                 " GiB, more than half of this machine's memory");
        builder_.setFilm(film);
    }

    void readIntegrator(JsonObjectReader r) {
        const IntegratorFactory make = integratorRegistry().factoryFor(r, "path");
        builder_.setIntegrator(make(r));
        r.finish();
    }

    void readMaterials(const Json& all) {
        for (auto it = all.begin(); it != all.end(); ++it) {
            JsonObjectReader m(it.value(), jsonPointerAppend("/materials", it.key()), path_);
            const MaterialFactory make = materialRegistry().factoryFor(m);
            MaterialContext context;
            context.directory = directory_;
            context.fields = hasFields_ ? &fields_ : nullptr;
            Material material = make(m, context);
            material.name = it.key();
            m.finish();
            builder_.addMaterial(std::move(material));
        }
    }

    void readLights(const Json& lights, const std::string& pointer) {
        if (!lights.is_array()) throw InputError(path_, pointer, "expected an array of lights");
        for (size_t i = 0; i < lights.size(); ++i) {
            JsonObjectReader l(lights[i], jsonPointerAppend(pointer, i), path_);
            const LightFactory make = lightRegistry().factoryFor(l);
            make(l, builder_, i);
            l.finish();
        }
    }

    int materialNamed(JsonObjectReader& r) {
        const std::string name = r.string("material");
        const std::optional<int> index = builder_.findMaterial(name);
        if (!index) {
            std::string message = "unknown material \"" + name + "\"";
            if (auto near = geometry::nearestName(name, builder_.materialNames())) message += " (did you mean \"" + *near + "\"?)";
            r.fail("material", message);
        }
        return *index;
    }

    /// A field an object shows, whose surface must fit single-precision rays.
    geometry::FieldProgram compileShown(const std::string& field) {
        if (const auto it = shownPrograms_.find(field); it != shownPrograms_.end()) return it->second;
        geometry::FieldProgram program = fields_.compile(field);
        const geometry::Box3& box = program.bounds();
        const double reach = std::max(box.lower.cwiseAbs().maxCoeff(), box.upper.cwiseAbs().maxCoeff());
        if (std::isfinite(reach) && reach > kMaxCoordinate && !box.isEmpty()) {
            std::ostringstream message;
            message << "its surface may reach " << std::setprecision(3) << reach
                    << " from the origin; beyond 1e15 single-precision rays cannot represent it";
            throw InputError(path_, jsonPointerAppend("/fields", field), message.str());
        }
        shownPrograms_.emplace(field, program);
        return program;
    }

    void validateMesh(TriangleMesh& mesh, JsonObjectReader& r, const std::string& key) {
        const bool drop = r.boolean("drop_degenerate", false);
        for (size_t i = 0; i < mesh.indices.size(); ++i)
            if (mesh.indices[i] >= mesh.vertexCount())
                r.fail(key, "triangle " + std::to_string(i / 3) + " refers to vertex " + std::to_string(mesh.indices[i]) +
                                ", but there are only " + std::to_string(mesh.vertexCount()));
        if (drop) {
            mesh.dropDegenerateTriangles();
            if (mesh.triangleCount() == 0) r.fail(key, "every triangle is degenerate");
        } else if (const long bad = mesh.firstDegenerateTriangle(); bad >= 0) {
            r.fail(key, "triangle " + std::to_string(bad) +
                            " is degenerate (zero area); set \"drop_degenerate\": true to skip such triangles");
        }
    }

    // What an object asks for, read and checked before anything is built:
    // a typo in the last object (or in a field it shows) fails at once,
    // not after the fits, surfaces, meshes and particles of the others.
    struct ObjectRequest {
        explicit ObjectRequest(JsonObjectReader r) : reader(std::move(r)) {}
        JsonObjectReader reader;
        SceneObject object;  ///< name, material, transform, kind
        std::string field;   ///< shown field, or empty for a mesh
        std::string as;
        geometry::PolygonizeOptions polygonize;
        geometry::ParticleOptions particles;
        double discScale = 0.9;
        std::string meshFile;  ///< a mesh file, resolved against the scene's folder
        TriangleMesh mesh;     ///< an inline mesh, checked
        bool smooth = false;
    };

    ObjectRequest readObject(const Json& object, const std::string& pointer) {
        ObjectRequest q(JsonObjectReader(object, pointer, path_));
        JsonObjectReader& r = q.reader;
        SceneObject& o = q.object;
        o.name = r.string("name", pointer);
        o.material = materialNamed(r);
        if (r.has("transform")) {
            JsonObjectReader t = r.object("transform");
            o.worldFromObject = readTransform(t);
            const double inverse = o.worldFromObject.inverse().topRows<3>().cwiseAbs().maxCoeff();
            if (!(o.worldFromObject.topRows<3>().cwiseAbs().maxCoeff() <= kMaxTransformEntry) ||
                !(inverse <= kMaxTransformEntry))
                r.fail("transform", "scales or translations beyond 1e9 (or their inverses) cannot be represented by "
                                    "single-precision rays");
        }

        const bool hasField = r.has("field"), hasMesh = r.has("mesh"), hasInline = r.has("vertices");
        if (int(hasField) + int(hasMesh) + int(hasInline) != 1)
            r.failHere("an object needs exactly one of \"field\", \"mesh\" (a file) or \"vertices\"/\"indices\"");
        if (hasField) {
            q.field = r.string("field");
            if (!fields_.contains(q.field)) {
                std::string message = "unknown field \"" + q.field + "\"";
                if (auto near = geometry::nearestName(q.field, fields_.names())) message += " (did you mean \"" + *near + "\"?)";
                r.fail("field", message);
            }
            q.as = r.choice("as", {"implicit", "mesh", "particles"}, "implicit");
            // Mesh settings are read whatever "as" says, so --as can switch.
            q.polygonize.method = r.choice("method", {"marching_cubes", "adaptive"}, "marching_cubes") == "adaptive"
                                      ? geometry::PolygonizeMethod::Adaptive
                                      : geometry::PolygonizeMethod::MarchingCubes;
            q.polygonize.resolution =
                static_cast<int>(r.integer("resolution", 0, 1, geometry::kMaxPolygonizeResolution));
            q.polygonize.tolerance = r.has("tolerance") ? r.positiveNumber("tolerance") : 0.0;
            // Particle settings likewise.
            if (r.has("spacing")) {
                q.particles.spacing = r.positiveNumber("spacing");
                if (r.has("count")) r.fail("count", "give \"count\" or \"spacing\", not both");
            } else {
                q.particles.count = size_t(r.integer("count", 5000, 1, 10000000));
            }
            q.particles.seed = uint64_t(r.integer("seed", 1, 0, std::numeric_limits<int64_t>::max()));
            q.discScale = r.number("disc_scale", 0.9);
            if (!(q.discScale > 0 && q.discScale <= 4)) r.fail("disc_scale", "must be in (0, 4]");
            if (overrides_.fieldMode == SceneOverrides::FieldMode::Implicit) q.as = "implicit";
            if (overrides_.fieldMode == SceneOverrides::FieldMode::Mesh) q.as = "mesh";
            o.kind = q.as == "mesh"        ? SceneObject::Kind::Mesh
                     : q.as == "particles" ? SceneObject::Kind::Discs
                                           : SceneObject::Kind::Implicit;
        } else {
            o.kind = SceneObject::Kind::Mesh;
            if (hasMesh) {
                std::filesystem::path p(r.string("mesh"));
                if (p.is_relative()) p = directory_ / p;
                q.meshFile = p.string();
            } else {
                const std::vector<double> v = r.numbers("vertices");
                if (v.size() % 3 != 0 || v.empty()) r.fail("vertices", "expected x y z triples");
                for (double x : v) q.mesh.positions.push_back(float(x));
                const Json& idx = r.value("indices");
                if (!idx.is_array() || idx.empty() || idx.size() % 3 != 0)
                    r.fail("indices", "expected a non-empty array of vertex indices, three per triangle");
                for (size_t i = 0; i < idx.size(); ++i) {
                    // Parsed JSON stores non-negative integers as unsigned;
                    // descriptions built in code may hold signed ones.
                    if (!idx[i].is_number_integer() || idx[i].get<int64_t>() < 0 ||
                        idx[i].get<int64_t>() > std::numeric_limits<uint32_t>::max())
                        throw InputError(path_, jsonPointerAppend(r.pointerOf("indices"), i), "expected a vertex index (a whole number >= 0)");
                    q.mesh.indices.push_back(idx[i].get<uint32_t>());
                }
                validateMesh(q.mesh, r, "indices");
                if (r.has("uvs")) {
                    const std::vector<double> uv = r.numbers("uvs");
                    if (uv.size() != 2 * q.mesh.vertexCount())
                        r.fail("uvs", "expected u v per vertex: " + std::to_string(2 * q.mesh.vertexCount()) +
                                          " numbers, found " + std::to_string(uv.size()));
                    for (double x : uv) q.mesh.uvs.push_back(float(x));
                }
            }
            if (hasMesh) r.boolean("drop_degenerate", false);  // read again when the file is loaded
            q.smooth = r.boolean("smooth", false);
        }
        r.finish();
        return q;
    }

    void buildObject(ObjectRequest& q) {
        JsonObjectReader& r = q.reader;
        SceneObject o = q.object;
        if (!q.field.empty()) {
            if (q.as == "mesh") {
                o.shape = polygonizedMesh(q.field, q.polygonize, r);
            } else if (q.as == "particles") {
                o.shape = particleDiscs(q.field, q.particles, q.discScale, r);
            } else {
                auto it = surfaceIndex_.find(q.field);
                if (it == surfaceIndex_.end()) {
                    std::unique_ptr<geometry::ImplicitSurface> surface;
                    try {
                        surface = std::make_unique<geometry::ImplicitSurface>(compileShown(q.field));
                    } catch (const std::invalid_argument& e) {
                        throw InputError(path_, jsonPointerAppend("/fields", q.field), e.what());
                    }
                    it = surfaceIndex_.emplace(q.field, builder_.addSurface(std::move(surface))).first;
                }
                o.shape = it->second;
            }
        } else {
            // One mesh per file and settings, shared by every object that
            // uses it: objects placed by their transforms are instances of
            // one Embree scene, not copies.
            const std::string key = q.meshFile + "|" + (q.smooth ? "smooth" : "flat") + "|" +
                                    (r.boolean("drop_degenerate", false) ? "drop" : "keep");
            if (!q.meshFile.empty()) {
                if (const auto it = meshFileIndex_.find(key); it != meshFileIndex_.end()) {
                    o.shape = it->second;
                    builder_.addObject(o);
                    return;
                }
            }
            TriangleMesh mesh = std::move(q.mesh);
            if (!q.meshFile.empty()) {
                try {
                    mesh = loadTriangleMesh(q.meshFile);
                } catch (const InputError& e) {
                    throw InputError(path_, r.pointerOf("mesh"), "\"" + q.meshFile + "\": " + e.message() +
                                                                     (e.where().empty() ? "" : " (" + e.where() + ")"));
                }
                validateMesh(mesh, r, "mesh");
            }
            if (q.smooth) mesh.computeSmoothNormals();
            o.shape = builder_.addMesh(std::move(mesh));
            if (!q.meshFile.empty()) meshFileIndex_.emplace(key, o.shape);
        }
        builder_.addObject(o);
    }

    // One set of particles per field and settings, shown as discs of
    // radius disc_scale times each particle's (half the local spacing).
    int particleDiscs(const std::string& field, const geometry::ParticleOptions& options, double discScale,
                      JsonObjectReader& r) {
        const std::string key = field + "|" + std::to_string(options.count) + "|" + std::to_string(options.spacing) +
                                "|" + std::to_string(options.seed) + "|" + std::to_string(discScale);
        if (const auto it = discIndex_.find(key); it != discIndex_.end()) return it->second;
        geometry::ParticleSampling sampling;
        try {
            sampling = geometry::spreadParticles(compileShown(field), options);
        } catch (const std::invalid_argument& e) {
            r.failHere(std::string("cannot spread particles on field \"") + field + "\": " + e.what());
        }
        DiscPoints discs;
        for (const geometry::SurfaceParticle& p : sampling.particles) {
            for (int k = 0; k < 3; ++k) discs.centersAndRadii.push_back(float(p.position[k]));
            discs.centersAndRadii.push_back(float(discScale * p.radius));
            for (int k = 0; k < 3; ++k) discs.normals.push_back(float(p.normal[k]));
        }
        const int index = builder_.addDiscs(std::move(discs));
        discIndex_.emplace(key, index);
        return index;
    }

    // One mesh per field and settings, shared by every object that uses it.
    int polygonizedMesh(const std::string& field, const geometry::PolygonizeOptions& options, JsonObjectReader& r) {
        const std::string key = field + "|" + std::to_string(int(options.method)) + "|" +
                                std::to_string(options.resolution) + "|" + std::to_string(options.tolerance);
        if (const auto it = meshIndex_.find(key); it != meshIndex_.end()) return it->second;
        geometry::Polygonization result;
        try {
            result = geometry::polygonize(compileShown(field), options);
        } catch (const std::invalid_argument& e) {
            r.failHere(std::string("cannot polygonize field \"") + field + "\": " + e.what());
        }
        for (const std::string& w : result.warnings) builder_.addWarning(r.pointer() + ": " + w);
        TriangleMesh mesh;
        for (size_t v = 0; v < result.mesh.vertices.size(); ++v)
            for (int k = 0; k < 3; ++k) {
                mesh.positions.push_back(float(result.mesh.vertices[v][k]));
                mesh.normals.push_back(float(result.mesh.normals[v][k]));
            }
        for (const auto& t : result.mesh.triangles) mesh.indices.insert(mesh.indices.end(), t.begin(), t.end());
        // Slivers that round to zero area in single precision carry no surface.
        mesh.dropDegenerateTriangles();
        const int index = builder_.addMesh(std::move(mesh));
        meshIndex_.emplace(key, index);
        return index;
    }

    SceneBuilder builder_;
    std::string path_;
    SceneOverrides overrides_;
    std::filesystem::path directory_;
    geometry::FieldLibrary fields_;
    bool hasFields_ = false;
    std::map<std::string, int> discIndex_;
    std::map<std::string, int> surfaceIndex_;
    std::map<std::string, geometry::FieldProgram> shownPrograms_;  ///< compiled once per field
    std::map<std::string, int> meshIndex_;
    std::map<std::string, int> meshFileIndex_;  ///< by file, smoothing and dropping
};

}  // namespace


}  // namespace isotrace

namespace isotrace {

std::unique_ptr<Scene> loadScene(const std::string& path, const SceneOverrides& overrides) {
    return SceneLoader(path, overrides).load();
}

std::unique_ptr<Scene> loadSceneDescription(const geometry::Json& root, const std::string& path,
                                            const SceneOverrides& overrides) {
    return SceneLoader(path, overrides).load(root);
}

std::vector<std::string> sceneInputFiles(const std::string& path) {
    std::vector<std::string> files{path};
    Json root;
    try {
        root = geometry::parseJsonFile(path);
    } catch (const std::exception&) {
        return files;
    }
    // Any string that names an existing file beside the scene is taken for
    // an input: file keys differ by type, and a false match only refuses
    // an output name that would have shadowed a file anyway. An explicit
    // stack: the depth of a scene file is the user's.
    const std::filesystem::path directory = std::filesystem::absolute(path).parent_path();
    std::vector<const Json*> pending{&root};
    while (!pending.empty()) {
        const Json* j = pending.back();
        pending.pop_back();
        if (j->is_string()) {
            std::filesystem::path named(j->get<std::string>());
            if (named.empty()) continue;
            if (named.is_relative()) named = directory / named;
            std::error_code ec;
            if (std::filesystem::is_regular_file(named, ec)) files.push_back(named.string());
        } else if (j->is_structured()) {
            for (const Json& child : *j) pending.push_back(&child);
        }
    }
    return files;
}

}  // namespace isotrace
