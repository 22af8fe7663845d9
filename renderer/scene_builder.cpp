#include "renderer/scene_builder.h"

#include <stdexcept>
#include <type_traits>

#include "renderer/integrator.h"
#include "renderer/object_lights.h"

namespace isotrace {

namespace {

// A plugin made by its registry from a description built in code; errors
// name the builder, as there is no file.
template <class Factory, class... Extra>
auto makePlugin(const Registry<Factory>& registry, const geometry::Json& description, Extra&&... extra) {
    geometry::JsonObjectReader r(description, "", "SceneBuilder");
    const Factory& make = registry.factoryFor(r);
    if constexpr (std::is_void_v<decltype(make(r, std::forward<Extra>(extra)...))>) {
        make(r, std::forward<Extra>(extra)...);
        r.finish();
    } else {
        auto made = make(r, std::forward<Extra>(extra)...);
        r.finish();
        return made;
    }
}

}  // namespace

SceneBuilder::SceneBuilder() : scene_(std::make_unique<Scene>()) { scene_->integrator = makeDefaultIntegrator(); }

int SceneBuilder::addMaterial(Material material) {
    const auto [it, added] = materialIndex_.emplace(material.name, int(scene_->materials.size()));
    if (!added) throw std::logic_error("material \"" + material.name + "\" added twice");
    scene_->materials.push_back(std::move(material));
    return it->second;
}

int SceneBuilder::addMaterial(const std::string& name, const geometry::Json& description) {
    Material m = makePlugin(materialRegistry(), description, MaterialContext{});
    m.name = name;
    return addMaterial(std::move(m));
}

void SceneBuilder::setIntegrator(const geometry::Json& description) {
    setIntegrator(makePlugin(integratorRegistry(), description));
}

void SceneBuilder::addLight(const geometry::Json& description) {
    makePlugin(lightRegistry(), description, *this, lightDescriptions_++);
}

std::optional<int> SceneBuilder::findMaterial(const std::string& name) const {
    const auto it = materialIndex_.find(name);
    return it == materialIndex_.end() ? std::nullopt : std::optional<int>(it->second);
}

std::vector<std::string> SceneBuilder::materialNames() const {
    std::vector<std::string> names;
    for (const auto& [name, index] : materialIndex_) names.push_back(name);
    return names;
}

int SceneBuilder::addMesh(TriangleMesh mesh) {
    scene_->meshes.push_back(std::make_shared<TriangleMesh>(std::move(mesh)));
    return int(scene_->meshes.size() - 1);
}

int SceneBuilder::addSurface(std::unique_ptr<geometry::ImplicitSurface> surface) {
    scene_->surfaces.push_back(std::move(surface));
    return int(scene_->surfaces.size() - 1);
}

int SceneBuilder::addDiscs(DiscPoints discs) {
    scene_->discs.push_back(std::make_shared<DiscPoints>(std::move(discs)));
    return int(scene_->discs.size() - 1);
}

int SceneBuilder::addObject(const SceneObject& object) {
    const size_t shapes = object.kind == SceneObject::Kind::Mesh       ? scene_->meshes.size()
                          : object.kind == SceneObject::Kind::Implicit ? scene_->surfaces.size()
                                                                       : scene_->discs.size();
    if (object.shape < 0 || size_t(object.shape) >= shapes) throw std::logic_error("object placed with no such shape");
    if (object.material < 0 || size_t(object.material) >= scene_->materials.size())
        throw std::logic_error("object placed with no such material");
    scene_->objects.push_back(object);
    return int(scene_->objects.size() - 1);
}

int SceneBuilder::addEmitter(TriangleMesh mesh, const Emission& emission, const std::string& name) {
    // Emitters' materials are not named in the file: they take the object's
    // name, outside the namespace of the file's materials.
    Material m;
    m.name = name;
    m.emission = emission;
    scene_->materials.push_back(std::move(m));
    SceneObject o;
    o.kind = SceneObject::Kind::Mesh;
    o.name = name;
    o.shape = addMesh(std::move(mesh));
    o.material = int(scene_->materials.size() - 1);
    o.emitsAsOneLight = true;
    return addObject(o);
}

void SceneBuilder::addLight(std::unique_ptr<Light> light) { scene_->lights.push_back(std::move(light)); }

void SceneBuilder::setEnvironment(std::unique_ptr<Light> light) {
    if (hasEnvironment()) throw std::logic_error("a second environment light");
    scene_->environmentLight = int(scene_->lights.size());
    addLight(std::move(light));
}

std::unique_ptr<Scene> SceneBuilder::build() {
    if (!scene_) throw std::logic_error("SceneBuilder::build called twice");
    for (SceneObject& o : scene_->objects) {
        const Material& m = scene_->materials[o.material];
        if (!m.emission || o.kind != SceneObject::Kind::Mesh) continue;
        const TriangleMesh& mesh = *scene_->meshes[o.shape];
        std::vector<std::array<Vec3, 3>> triangles(mesh.triangleCount());
        for (size_t t = 0; t < mesh.triangleCount(); ++t)
            for (int k = 0; k < 3; ++k) {
                const Eigen::Vector4d p = o.worldFromObject * mesh.vertex(mesh.indices[3 * t + k]).homogeneous();
                triangles[t][k] = p.head<3>();
            }
        if (o.emitsAsOneLight) {
            o.areaLight = int(scene_->lights.size());
            scene_->lights.push_back(makeAreaLight(std::move(triangles), *m.emission));
            continue;
        }
        o.triangleLights.assign(triangles.size(), -1);
        for (size_t t = 0; t < triangles.size(); ++t) {
            const auto& [a, b, c] = triangles[t];
            if (!((b - a).cross(c - a).norm() > 0.0)) continue;  // no area: never sampled, never hit
            o.triangleLights[t] = int(scene_->lights.size());
            scene_->lights.push_back(makeAreaLight({triangles[t]}, *m.emission));
        }
        scene_->meshLights.push_back(makeAreaLight(std::move(triangles), *m.emission));
    }
    scene_->commit();
    // Emissive implicit objects are traced when sampled: their lights come
    // once the scene's structures exist.
    for (SceneObject& o : scene_->objects) {
        const Material& m = scene_->materials[o.material];
        if (!m.emission || o.kind != SceneObject::Kind::Implicit) continue;
        o.areaLight = int(scene_->lights.size());
        scene_->lights.push_back(makeImplicitEmitterLight(*scene_, o, *m.emission));
    }
    addMirrorImages(*scene_);
    std::vector<bool> ofATriangle(scene_->lights.size(), false);
    for (const SceneObject& o : scene_->objects)
        for (const int light : o.triangleLights)
            if (light >= 0) ofATriangle[size_t(light)] = true;
    for (size_t l = 0; l < scene_->lights.size(); ++l)
        if (!ofATriangle[l]) scene_->groupedLights.push_back(scene_->lights[l].get());
    for (const auto& light : scene_->meshLights) scene_->groupedLights.push_back(light.get());
    scene_->lightSampler = LightSampler(scene_->lights, scene_->integrator->lightSampling());
    scene_->cameraInteriors = interiorsAt(*scene_, scene_->camera.from);
    return std::move(scene_);
}

}  // namespace isotrace
