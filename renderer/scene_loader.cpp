#include "scene_loader.h"

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <unistd.h>

#include "geometry/field_parser.h"
#include "geometry/json_reader.h"
#include "geometry/polygonizer.h"
#include "geometry/transform_description.h"

namespace isotrace {

using geometry::InputError;
using geometry::Json;
using geometry::JsonObjectReader;
using geometry::jsonPointerAppend;

namespace {

constexpr int kMaxImageSide = 1 << 16;
constexpr int kMaxSamplesPerPixel = 1 << 20;
constexpr int kDiskSegments = 64;

RGB readColor(JsonObjectReader& r, const std::string& key, const RGB& fallback, bool nonNegative = true) {
    if (!r.has(key)) return fallback;
    const Vec3 v = r.vec3(key);
    if (nonNegative && (v.array() < 0).any()) r.fail(key, "colour components must not be negative");
    return v.array();
}

Mat4 readTransform(JsonObjectReader& r) {
    Mat4 m = Mat4::Identity();
    if (r.has("matrix")) {
        const Json& j = r.value("matrix");
        const std::string pointer = r.pointerOf("matrix");
        if (!j.is_array() || j.size() != 4) throw InputError(r.file(), pointer, "expected 4 rows of 4 numbers");
        for (int row = 0; row < 4; ++row) {
            const std::string rp = jsonPointerAppend(pointer, row);
            if (!j[row].is_array() || j[row].size() != 4) throw InputError(r.file(), rp, "expected a row of 4 numbers");
            for (int col = 0; col < 4; ++col)
                m(row, col) = JsonObjectReader::asNumber(j[row][col], jsonPointerAppend(rp, col), r.file());
        }
        if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1)) r.fail("matrix", "the last row must be [0, 0, 0, 1] (affine)");
        for (const char* key : {"translate", "rotate", "scale"})
            if (r.has(key)) r.fail(key, "give either \"matrix\" or translate/rotate/scale, not both");
    } else {
        const geometry::AffineDescription affine = geometry::readScaleRotateTranslate(r);
        m.topLeftCorner<3, 3>() = affine.linear;
        m.topRightCorner<3, 1>() = affine.translation;
    }
    const double det = m.topLeftCorner<3, 3>().determinant();
    if (!(std::abs(det) > 1e-12) || !std::isfinite(det)) r.failHere("transform is singular (determinant " + std::to_string(det) + ")");
    r.finish();
    return m;
}

class SceneLoader {
public:
    SceneLoader(const std::string& path, const SceneOverrides& overrides)
        : path_(path), overrides_(overrides), directory_(std::filesystem::path(path).parent_path()) {}

    std::unique_ptr<Scene> load() { return load(geometry::parseJsonFile(path_)); }

    std::unique_ptr<Scene> load(const Json& root) {
        JsonObjectReader r(root, "", path_);
        scene_ = std::make_unique<Scene>();
        scene_->sourceFile = path_;
        if (r.has("camera")) readCamera(r.object("camera"));
        if (r.has("film")) readFilm(r.object("film"));
        applyOverrides();
        if (r.has("integrator")) readIntegrator(r.object("integrator"));
        if (const Json* materials = r.optionalValue("materials")) {
            if (!materials->is_object()) r.fail("materials", "expected an object mapping material names to materials");
            readMaterials(*materials);
        }
        if (const Json* fields = r.optionalValue("fields")) {
            fields_ = geometry::FieldLibrary(*fields, "/fields", path_);
        }
        const Json& objects = r.value("objects");
        if (!objects.is_array()) r.fail("objects", "expected an array of objects");
        if (objects.empty()) r.fail("objects", "the scene is empty: add at least one object");
        if (r.has("lights")) readLights(r.value("lights"), r.pointerOf("lights"));
        for (size_t i = 0; i < objects.size(); ++i) readObject(objects[i], jsonPointerAppend("/objects", i));
        r.finish();
        addAreaLightsOfEmissiveMeshes();
        scene_->commit();
        return std::move(scene_);
    }

private:
    void readCamera(JsonObjectReader c) {
        c.choice("type", {"perspective"}, "perspective");
        CameraSettings& cam = scene_->camera;
        cam.from = c.vec3("from", cam.from);
        cam.to = c.vec3("to", cam.to);
        cam.up = c.vec3("up", cam.up);
        cam.verticalFovDegrees = c.number("fov", cam.verticalFovDegrees);
        if (!(cam.verticalFovDegrees > 0 && cam.verticalFovDegrees < 180)) c.fail("fov", "must be between 0 and 180 degrees");
        cam.aperture = c.number("aperture", 0.0);
        if (cam.aperture < 0) c.fail("aperture", "must not be negative");
        cam.focusDistance = c.number("focus_distance", 0.0);
        if (cam.focusDistance < 0) c.fail("focus_distance", "must not be negative");
        if (!((cam.to - cam.from).norm() > 0)) c.fail("to", "must differ from \"from\"");
        if (cam.focusDistance == 0) cam.focusDistance = (cam.to - cam.from).norm();
        if (!((cam.to - cam.from).normalized().cross(cam.up).norm() > 1e-9)) c.fail("up", "must not be parallel to the view direction");
        c.finish();
    }

    void readFilm(JsonObjectReader f) {
        FilmSettings& film = scene_->film;
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
            if (film.filter.type == FilterType::Gaussian) film.filter.sigma = filter.positiveNumber("sigma", 0.5);
            filter.finish();
        }
        f.finish();
    }

    void applyOverrides() {
        FilmSettings& film = scene_->film;
        if (overrides_.width > 0) film.width = overrides_.width;
        if (overrides_.height > 0) film.height = overrides_.height;
        if (overrides_.samplesPerPixel > 0) film.samplesPerPixel = overrides_.samplesPerPixel;
        const double bytes = estimateFilmBytes(film.width, film.height);
        const double available = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
        if (bytes > 0.5 * available)
            throw InputError(path_, "/film", "a " + std::to_string(film.width) + "x" + std::to_string(film.height) +
                                                 " image needs about " + std::to_string(bytes / (1 << 30)) +
                                                 " GiB, more than half of this machine's memory");
    }

    void readIntegrator(JsonObjectReader r) {
        IntegratorSettings& s = scene_->integrator;
        const std::string type = r.choice("type", {"path", "whitted"}, "path");
        s.type = type == "path" ? IntegratorSettings::Type::Path : IntegratorSettings::Type::Whitted;
        s.maxDepth = static_cast<int>(r.integer("max_depth", s.maxDepth, 1, 1000));
        s.russianRouletteDepth = static_cast<int>(r.integer("rr_depth", s.russianRouletteDepth, 1, 1000));
        r.finish();
    }

    void readMaterials(const Json& all) {
        for (auto it = all.begin(); it != all.end(); ++it) {
            JsonObjectReader m(it.value(), jsonPointerAppend("/materials", it.key()), path_);
            Material mat;
            mat.name = it.key();
            const std::string type = m.choice("type", {"diffuse", "mirror", "emissive"}, "");
            if (type == "diffuse") {
                mat.type = Material::Type::Diffuse;
                mat.albedo = readColor(m, "albedo", mat.albedo);
                if ((mat.albedo > 1.0).any()) m.fail("albedo", "albedo above 1 creates energy");
            } else if (type == "mirror") {
                mat.type = Material::Type::Mirror;
                mat.reflectance = readColor(m, "reflectance", mat.reflectance);
                if ((mat.reflectance > 1.0).any()) m.fail("reflectance", "reflectance above 1 creates energy");
            } else {
                mat.type = Material::Type::Emissive;
                mat.radiance = readColor(m, "radiance", RGB::Ones());
                mat.twoSided = m.boolean("two_sided", false);
            }
            m.finish();
            materialIndex_[mat.name] = static_cast<int>(scene_->materials.size());
            scene_->materials.push_back(mat);
        }
    }

    void readLights(const Json& lights, const std::string& pointer) {
        if (!lights.is_array()) throw InputError(path_, pointer, "expected an array of lights");
        for (size_t i = 0; i < lights.size(); ++i) {
            JsonObjectReader l(lights[i], jsonPointerAppend(pointer, i), path_);
            const std::string type = l.choice("type", {"point", "directional", "quad", "disk", "environment"}, "");
            if (type == "point") {
                scene_->lights.push_back(Light::point(l.vec3("position"), readColor(l, "intensity", RGB::Ones())));
            } else if (type == "directional") {
                const Vec3 d = l.vec3("direction");
                if (!(d.norm() > 0)) l.fail("direction", "must not be the zero vector");
                scene_->lights.push_back(Light::directional(d, readColor(l, "irradiance", RGB::Ones())));
            } else if (type == "environment") {
                if (scene_->environmentLight >= 0) l.failHere("only one environment light is allowed");
                scene_->environmentLight = static_cast<int>(scene_->lights.size());
                scene_->lights.push_back(Light::environment(readColor(l, "radiance", RGB::Ones())));
            } else {
                // Area lights are emissive geometry: visible, and sampled by area.
                const RGB radiance = readColor(l, "radiance", RGB::Ones());
                const bool twoSided = l.boolean("two_sided", false);
                TriangleMesh mesh;
                if (type == "quad") {
                    const Vec3 corner = l.vec3("corner"), e1 = l.vec3("edge1"), e2 = l.vec3("edge2");
                    if (!(e1.cross(e2).norm() > 0)) l.fail("edge2", "the quad's edges must not be parallel or zero");
                    for (const Vec3& p : {corner, Vec3(corner + e1), Vec3(corner + e1 + e2), Vec3(corner + e2)})
                        mesh.positions.insert(mesh.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
                    mesh.indices = {0, 1, 2, 0, 2, 3};
                } else {
                    const Vec3 center = l.vec3("center"), normal = l.vec3("normal", Vec3(0, -1, 0));
                    const double radius = l.positiveNumber("radius");
                    if (!(normal.norm() > 0)) l.fail("normal", "must not be the zero vector");
                    const Vec3 n = normal.normalized();
                    const Vec3 a = (std::abs(n.x()) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0)).cross(n).normalized();
                    const Vec3 b = n.cross(a);
                    // A fan of kDiskSegments triangles; sampling uses the same triangles.
                    mesh.positions.insert(mesh.positions.end(), {float(center.x()), float(center.y()), float(center.z())});
                    for (int k = 0; k < kDiskSegments; ++k) {
                        const double phi = 2.0 * std::numbers::pi * k / kDiskSegments;
                        const Vec3 p = center + radius * (std::cos(phi) * a + std::sin(phi) * b);
                        mesh.positions.insert(mesh.positions.end(), {float(p.x()), float(p.y()), float(p.z())});
                        mesh.indices.insert(mesh.indices.end(), {0u, uint32_t(1 + k), uint32_t(1 + (k + 1) % kDiskSegments)});
                    }
                }
                addEmitterObject(std::move(mesh), radiance, twoSided, "light " + std::to_string(i));
            }
            l.finish();
        }
    }

    int addEmitterObject(TriangleMesh mesh, const RGB& radiance, bool twoSided, const std::string& name) {
        Material m;
        m.type = Material::Type::Emissive;
        m.name = name;
        m.radiance = radiance;
        m.twoSided = twoSided;
        scene_->materials.push_back(m);
        SceneObject o;
        o.kind = SceneObject::Kind::Mesh;
        o.name = name;
        o.shape = static_cast<int>(scene_->meshes.size());
        o.material = static_cast<int>(scene_->materials.size() - 1);
        scene_->meshes.push_back(std::make_shared<TriangleMesh>(std::move(mesh)));
        scene_->objects.push_back(o);
        return static_cast<int>(scene_->objects.size() - 1);
    }

    int materialNamed(JsonObjectReader& r) {
        const std::string name = r.string("material");
        const auto it = materialIndex_.find(name);
        if (it == materialIndex_.end()) {
            std::vector<std::string> names;
            for (const auto& [n, i] : materialIndex_) names.push_back(n);
            std::string message = "unknown material \"" + name + "\"";
            if (auto near = geometry::nearestName(name, names)) message += " (did you mean \"" + *near + "\"?)";
            r.fail("material", message);
        }
        return it->second;
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

    void readObject(const Json& object, const std::string& pointer) {
        JsonObjectReader r(object, pointer, path_);
        SceneObject o;
        o.name = r.string("name", pointer);
        o.material = materialNamed(r);
        if (r.has("transform")) {
            JsonObjectReader t = r.object("transform");
            o.worldFromObject = readTransform(t);
        }

        const bool hasField = r.has("field"), hasMesh = r.has("mesh"), hasInline = r.has("vertices");
        if (int(hasField) + int(hasMesh) + int(hasInline) != 1)
            r.failHere("an object needs exactly one of \"field\", \"mesh\" (a file) or \"vertices\"/\"indices\"");
        if (hasField) {
            const std::string field = r.string("field");
            if (!fields_.contains(field)) {
                std::string message = "unknown field \"" + field + "\"";
                if (auto near = geometry::nearestName(field, fields_.names())) message += " (did you mean \"" + *near + "\"?)";
                r.fail("field", message);
            }
            std::string as = r.choice("as", {"implicit", "mesh"}, "implicit");
            // Mesh settings are read whatever "as" says, so --as can switch.
            geometry::PolygonizeOptions polygonize;
            polygonize.method = r.choice("method", {"marching_cubes", "adaptive"}, "marching_cubes") == "adaptive"
                                    ? geometry::PolygonizeMethod::Adaptive
                                    : geometry::PolygonizeMethod::MarchingCubes;
            polygonize.resolution =
                static_cast<int>(r.integer("resolution", 0, 1, geometry::kMaxPolygonizeResolution));
            polygonize.tolerance = r.has("tolerance") ? r.positiveNumber("tolerance") : 0.0;
            if (overrides_.fieldMode == SceneOverrides::FieldMode::Implicit) as = "implicit";
            if (overrides_.fieldMode == SceneOverrides::FieldMode::Mesh) as = "mesh";
            if (as == "mesh") {
                o.kind = SceneObject::Kind::Mesh;
                o.shape = polygonizedMesh(field, polygonize, r);
            } else {
                o.kind = SceneObject::Kind::Implicit;
                auto it = surfaceIndex_.find(field);
                if (it == surfaceIndex_.end()) {
                    geometry::FieldProgram program = fields_.compile(field);
                    try {
                        scene_->surfaces.push_back(std::make_unique<geometry::ImplicitSurface>(std::move(program)));
                    } catch (const std::invalid_argument& e) {
                        throw InputError(path_, jsonPointerAppend("/fields", field), e.what());
                    }
                    it = surfaceIndex_.emplace(field, int(scene_->surfaces.size() - 1)).first;
                }
                o.shape = it->second;
            }
        } else {
            o.kind = SceneObject::Kind::Mesh;
            std::string key = hasMesh ? "mesh" : "vertices";
            std::string cacheKey;
            TriangleMesh mesh;
            if (hasMesh) {
                const std::string file = r.string("mesh");
                std::filesystem::path p(file);
                if (p.is_relative()) p = directory_ / p;
                try {
                    mesh = loadTriangleMesh(p.string());
                } catch (const InputError& e) {
                    throw InputError(path_, r.pointerOf("mesh"), "\"" + p.string() + "\": " + e.message() +
                                                                     (e.where().empty() ? "" : " (" + e.where() + ")"));
                }
            } else {
                const std::vector<double> v = r.numbers("vertices");
                if (v.size() % 3 != 0 || v.empty()) r.fail("vertices", "expected x y z triples");
                for (double x : v) mesh.positions.push_back(float(x));
                const Json& idx = r.value("indices");
                if (!idx.is_array() || idx.empty() || idx.size() % 3 != 0)
                    r.fail("indices", "expected a non-empty array of vertex indices, three per triangle");
                for (size_t i = 0; i < idx.size(); ++i) {
                    // Parsed JSON stores non-negative integers as unsigned;
                    // descriptions built in code may hold signed ones.
                    if (!idx[i].is_number_integer() || idx[i].get<int64_t>() < 0 ||
                        idx[i].get<int64_t>() > std::numeric_limits<uint32_t>::max())
                        throw InputError(path_, jsonPointerAppend(r.pointerOf("indices"), i), "expected a vertex index (a whole number >= 0)");
                    mesh.indices.push_back(idx[i].get<uint32_t>());
                }
                key = "indices";
            }
            validateMesh(mesh, r, key);
            if (r.boolean("smooth", false)) mesh.computeSmoothNormals();
            o.shape = static_cast<int>(scene_->meshes.size());
            scene_->meshes.push_back(std::make_shared<TriangleMesh>(std::move(mesh)));
        }
        r.finish();
        scene_->objects.push_back(o);
    }

    // One mesh per field and settings, shared by every object that uses it.
    int polygonizedMesh(const std::string& field, const geometry::PolygonizeOptions& options, JsonObjectReader& r) {
        const std::string key = field + "|" + std::to_string(int(options.method)) + "|" +
                                std::to_string(options.resolution) + "|" + std::to_string(options.tolerance);
        if (const auto it = meshIndex_.find(key); it != meshIndex_.end()) return it->second;
        geometry::Polygonization result;
        try {
            result = geometry::polygonize(fields_.compile(field), options);
        } catch (const std::invalid_argument& e) {
            r.failHere(std::string("cannot polygonize field \"") + field + "\": " + e.what());
        }
        for (const std::string& w : result.warnings) scene_->warnings.push_back(r.pointer() + ": " + w);
        TriangleMesh mesh;
        for (size_t v = 0; v < result.mesh.vertices.size(); ++v)
            for (int k = 0; k < 3; ++k) {
                mesh.positions.push_back(float(result.mesh.vertices[v][k]));
                mesh.normals.push_back(float(result.mesh.normals[v][k]));
            }
        for (const auto& t : result.mesh.triangles) mesh.indices.insert(mesh.indices.end(), t.begin(), t.end());
        // Slivers that round to zero area in single precision carry no surface.
        mesh.dropDegenerateTriangles();
        const int index = static_cast<int>(scene_->meshes.size());
        scene_->meshes.push_back(std::make_shared<TriangleMesh>(std::move(mesh)));
        meshIndex_.emplace(key, index);
        return index;
    }

    void addAreaLightsOfEmissiveMeshes() {
        for (SceneObject& o : scene_->objects) {
            const Material& m = scene_->materials[o.material];
            if (!m.isEmissive() || o.kind != SceneObject::Kind::Mesh) continue;
            const TriangleMesh& mesh = *scene_->meshes[o.shape];
            std::vector<std::array<Vec3, 3>> triangles;
            for (size_t t = 0; t < mesh.triangleCount(); ++t) {
                std::array<Vec3, 3> tri;
                for (int k = 0; k < 3; ++k) {
                    const Eigen::Vector4d p = o.worldFromObject * mesh.vertex(mesh.indices[3 * t + k]).homogeneous();
                    tri[k] = p.head<3>();
                }
                triangles.push_back(tri);
            }
            o.areaLight = static_cast<int>(scene_->lights.size());
            scene_->lights.push_back(Light::area(std::move(triangles), m.radiance, m.twoSided));
        }
    }

    std::unique_ptr<Scene> scene_;
    std::string path_;
    SceneOverrides overrides_;
    std::filesystem::path directory_;
    geometry::FieldLibrary fields_;
    std::map<std::string, int> materialIndex_;
    std::map<std::string, int> surfaceIndex_;
    std::map<std::string, int> meshIndex_;
};

}  // namespace

double estimateFilmBytes(int width, int height) {
    // Double RGB sums, float RGB output, 8-bit preview.
    return double(width) * double(height) * (3 * 8 + 3 * 4 + 3);
}

}  // namespace isotrace

namespace isotrace {

std::unique_ptr<Scene> loadScene(const std::string& path, const SceneOverrides& overrides) {
    return SceneLoader(path, overrides).load();
}

std::unique_ptr<Scene> loadSceneDescription(const geometry::Json& root, const std::string& path,
                                            const SceneOverrides& overrides) {
    return SceneLoader(path, overrides).load(root);
}

}  // namespace isotrace
