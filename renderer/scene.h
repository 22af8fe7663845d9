// A scene ready to render: Embree's acceleration structure over instances of
// shared shapes (triangle meshes and implicit surfaces), plus what shading
// needs. SceneBuilder fills and commits it; scene files reach it through
// the loader.
#pragma once

#include <embree3/rtcore.h>
#include <memory>
#include <string>
#include <vector>

#include "geometry/tracing/implicit_surface.h"
#include "renderer/camera.h"
#include "renderer/image/film.h"
#include "renderer/interior_stack.h"
#include "renderer/light.h"
#include "renderer/light_sampler.h"
#include "renderer/material.h"
#include "renderer/plane_mirror.h"
#include "renderer/platform/embree_errors.h"
#include "renderer/triangle_mesh.h"

namespace isotrace {

class Integrator;

using geometry::Mat3;
using geometry::Mat4;

/// One instance in the scene: a shape placed by a transform.
struct SceneObject {
    enum class Kind { Mesh, Implicit, Discs };
    Kind kind = Kind::Mesh;
    std::string name;
    int shape = 0;  ///< index into Scene::meshes, Scene::surfaces or Scene::discs
    int material = 0;
    int areaLight = -1;  ///< index into Scene::lights for an emissive implicit object, quad or disk
    /// An emissive mesh's lights, one per triangle (-1 for one without
    /// area), so the light tree bounds and picks them one by one; empty
    /// for a quad or disk light, whose triangles make one flat light.
    std::vector<int> triangleLights;
    bool emitsAsOneLight = false;  ///< a quad or disk light (SceneBuilder::addEmitter)
    /// The light a hit on this object's primitive (a mesh's triangle) emits
    /// as, or -1.
    int lightAt(unsigned primitive) const {
        return triangleLights.empty() ? areaLight : triangleLights[primitive];
    }
    int planeMirror = -1;  ///< index into Scene::planeMirrors for flat mirrors
    Mat4 worldFromObject = Mat4::Identity();
    Mat3 normalFromObject = Mat3::Identity();  ///< inverse transpose of the linear part
    Mat4 objectFromWorld = Mat4::Identity();   ///< set by Scene::commit
    /// Object-space length of a unit world length (the mean scale's inverse).
    double objectFromWorldScale = 1.0;
};

struct SurfaceHit {
    double t = 0.0;
    Vec3 position;
    Vec3 geometricNormal;  ///< unit, world space, outward for implicits
    Vec3 shadingNormal;    ///< unit, world space
    /// The point and normal in the object's own space (what textures see).
    Vec3 objectPosition = Vec3::Zero();
    Vec3 objectNormal = Vec3(0, 0, 1);
    /// Texture coordinates interpolated over a mesh triangle that has them.
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    bool hasUv = false;
    double uvPerLength = 0.0;  ///< texture-coordinate units per object-space length on the triangle
    int object = -1;
    unsigned primitive = 0;
};

/// An Embree ray (and empty hit) from origin along direction up to tMax
/// (infinite allowed), single precision as Embree wants it.
RTCRayHit embreeRayHit(const Vec3& origin, const Vec3& direction, double tMax);

class Scene {
public:
    Scene();
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // Contents, filled by SceneBuilder.
    std::string sourceFile;
    CameraSettings camera;
    FilmSettings film;
    std::shared_ptr<const Integrator> integrator;
    std::vector<Material> materials;
    std::vector<std::shared_ptr<TriangleMesh>> meshes;
    std::vector<std::unique_ptr<geometry::ImplicitSurface>> surfaces;
    std::vector<std::shared_ptr<DiscPoints>> discs;
    std::vector<SceneObject> objects;
    std::vector<std::unique_ptr<const Light>> lights;
    /// The lights as an integrator that samples each one (whitted) sees
    /// them: every light, but each emissive mesh as one light over all its
    /// triangles (held in meshLights) instead of one per triangle.
    std::vector<const Light*> groupedLights;
    std::vector<std::unique_ptr<const Light>> meshLights;
    int environmentLight = -1;
    /// Flat mirrors, whose lights' images follow the scene's own lights.
    std::vector<PlaneMirror> planeMirrors;
    /// Chooses lights for next-event estimation (built with the scene).
    LightSampler lightSampler;
    /// The solids around the camera, where every camera path starts
    /// (set by SceneBuilder::build).
    InteriorStack cameraInteriors;
    /// Things a user should hear about that are not errors (an empty mesh).
    std::vector<std::string> warnings;

    /// Builds Embree's structures; call once after filling the contents.
    void commit();

    bool intersect(const Ray& ray, double tMax, SurfaceHit& hit) const;
    /// True when something blocks the segment from origin along direction up to tMax.
    bool occluded(const Vec3& origin, const Vec3& direction, double tMax) const;

    /// The Embree device, created on the first call.
    RTCDevice device() const;
    /// The world bounds of every object (after commit).
    geometry::Box3 bounds() const;
    /// The Embree scene of the shape an object places, in the shape's own
    /// space (after commit): for tracing one object alone. A mesh's or a
    /// surface's is built on the first call when no object instances it
    /// (not thread-safe: ask while loading).
    RTCScene shapeScene(const SceneObject& object) const {
        if (object.kind != SceneObject::Kind::Discs) buildShapeScene(shapeIndex(object));  // discs' are always built
        return shapeScenes_[shapeIndex(object)];
    }

private:
    /// Mesh and implicit objects with no transform are attached to the top
    /// scene as they are, not instanced.
    static bool attachedAsIs(const SceneObject& object);
    /// A shape's place in shapeScenes_: meshes, then surfaces, then disc sets.
    size_t shapeIndex(const SceneObject& object) const;
    /// Fills and commits a mesh's or surface's own scene, once (see commit).
    void buildShapeScene(size_t shape) const;

    mutable EmbreeErrorRecord embreeErrors_;  ///< checked after each build
    mutable RTCDevice device_ = nullptr;
    mutable std::vector<bool> shapeSceneBuilt_;
    RTCScene top_ = nullptr;
    std::vector<RTCScene> shapeScenes_;
};

}  // namespace isotrace
