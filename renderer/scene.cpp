#include "renderer/scene.h"

#include <cmath>
#include <limits>
#include <new>
#include <string>
#include <stdexcept>

#include "geometry/errors.h"
#include "geometry/tracing/embree_implicit_geometry.h"

namespace isotrace {

Scene::Scene() = default;

Scene::~Scene() {
    for (RTCScene s : shapeScenes_) rtcReleaseScene(s);
    if (top_) rtcReleaseScene(top_);
    if (device_) rtcReleaseDevice(device_);
}

// Created when first needed, not with the scene: commands that trace no
// rays never start Embree's threads. Embree picks its own kernels for the CPU.
RTCDevice Scene::device() const {
    if (!device_) {
        device_ = rtcNewDevice(nullptr);
        if (!device_) {
            const RTCError code = rtcGetDeviceError(nullptr);
            if (code == RTC_ERROR_OUT_OF_MEMORY) throw std::bad_alloc();
            throw geometry::InternalError("cannot create an Embree device (Embree error " + std::to_string(int(code)) + ")");
        }
        embreeErrors_.attachTo(device_);
    }
    return device_;
}

namespace {
// A mesh's triangles as an Embree geometry of `scene` with id `id`, its
// buffers shared (an empty mesh adds nothing: there is nothing to hit).
void attachTriangles(RTCDevice device, RTCScene scene, const TriangleMesh& mesh, unsigned id) {
    if (mesh.triangleCount() == 0) return;
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.positions.data(), 0,
                               3 * sizeof(float), mesh.vertexCount());
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                               3 * sizeof(uint32_t), mesh.triangleCount());
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(scene, g, id);
    rtcReleaseGeometry(g);
}
}  // namespace

void Scene::commit() {
    device();  // created now, if nothing asked for it before
    // One Embree scene per mesh and per surface, shared by every object
    // that places it with a transform. A shape that objects place only as
    // it is goes into the top scene itself (below): its own scene is built
    // only if asked for (shapeScene).
    const size_t shapes = meshes.size() + surfaces.size();
    std::vector<bool> instanced(shapes, false);
    for (const SceneObject& o : objects)
        if (o.kind != SceneObject::Kind::Discs && !attachedAsIs(o)) instanced[shapeIndex(o)] = true;
    shapeSceneBuilt_.assign(shapes, false);
    for (size_t i = 0; i < shapes; ++i) {
        shapeScenes_.push_back(rtcNewScene(device_));
        if (instanced[i]) buildShapeScene(i);
    }
    for (const auto& set : discs) {
        RTCScene s = rtcNewScene(device_);
        if (set->count() > 0) {
            RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT);
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, set->centersAndRadii.data(), 0,
                                       4 * sizeof(float), set->count());
            rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_NORMAL, 0, RTC_FORMAT_FLOAT3, set->normals.data(), 0,
                                       3 * sizeof(float), set->count());
            rtcCommitGeometry(g);
            rtcAttachGeometry(s, g);
            rtcReleaseGeometry(g);
        }
        rtcCommitScene(s);
        shapeScenes_.push_back(s);
    }
    top_ = rtcNewScene(device_);
    for (size_t i = 0; i < objects.size(); ++i) {
        SceneObject& o = objects[i];
        o.normalFromObject = o.worldFromObject.topLeftCorner<3, 3>().inverse().transpose();
        o.objectFromWorld = o.worldFromObject.inverse();
        o.objectFromWorldScale = 1.0 / std::cbrt(std::abs(o.worldFromObject.topLeftCorner<3, 3>().determinant()));
        if (attachedAsIs(o)) {
            // Without an instance between, a ray skips Embree's instance
            // step: the CSG and tangle Whitted previews render 2-4% faster,
            // the 37,934-vertex mesh of bench/mpu_render (path, 16 spp) 7%.
            if (o.kind == SceneObject::Kind::Mesh)
                attachTriangles(device_, top_, *meshes[o.shape], static_cast<unsigned>(i));
            else
                geometry::attachImplicitSurfaceAs(device_, top_, *surfaces[o.shape], static_cast<unsigned>(i));
            continue;
        }
        RTCGeometry inst = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
        rtcSetGeometryInstancedScene(inst, shapeScenes_[shapeIndex(o)]);
        Eigen::Matrix<float, 3, 4> m = o.worldFromObject.topRows<3>().cast<float>();
        // Column-major 3x4, as Embree's FLOAT3X4_COLUMN_MAJOR expects.
        rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m.data());
        rtcCommitGeometry(inst);
        rtcAttachGeometryByID(top_, inst, static_cast<unsigned>(i));
        rtcReleaseGeometry(inst);
    }
    rtcCommitScene(top_);
    embreeErrors_.check("building the scene");
}

bool Scene::attachedAsIs(const SceneObject& object) {
    return object.kind != SceneObject::Kind::Discs && object.worldFromObject.isIdentity();
}

size_t Scene::shapeIndex(const SceneObject& object) const {
    switch (object.kind) {
        case SceneObject::Kind::Mesh: return object.shape;
        case SceneObject::Kind::Implicit: return meshes.size() + object.shape;
        case SceneObject::Kind::Discs: break;
    }
    return meshes.size() + surfaces.size() + object.shape;
}

void Scene::buildShapeScene(size_t shape) const {
    if (shapeSceneBuilt_[shape]) return;
    RTCScene s = shapeScenes_[shape];
    if (shape < meshes.size()) attachTriangles(device_, s, *meshes[shape], 0);
    else geometry::attachImplicitSurface(device_, s, *surfaces[shape - meshes.size()]);
    rtcCommitScene(s);
    embreeErrors_.check("building an object's own scene");
    shapeSceneBuilt_[shape] = true;
}

geometry::Box3 Scene::bounds() const {
    RTCBounds b;
    rtcGetSceneBounds(top_, &b);
    if (!(b.lower_x <= b.upper_x)) return {};
    return geometry::Box3(Vec3(b.lower_x, b.lower_y, b.lower_z), Vec3(b.upper_x, b.upper_y, b.upper_z));
}

namespace {
// What Embree accepts (its ray.valid()): finite, origin within 1.8e18. A
// ray it would abort on is treated as leaving the scene.
bool representable(const Vec3& origin, const Vec3& direction) {
    return origin.allFinite() && direction.allFinite() && origin.cwiseAbs().maxCoeff() < 1e18 &&
           direction.cwiseAbs().maxCoeff() < 1e18;
}
}  // namespace

RTCRayHit embreeRayHit(const Vec3& origin, const Vec3& direction, double tMax) {
    RTCRayHit rh;
    rh.ray.org_x = float(origin.x());
    rh.ray.org_y = float(origin.y());
    rh.ray.org_z = float(origin.z());
    rh.ray.dir_x = float(direction.x());
    rh.ray.dir_y = float(direction.y());
    rh.ray.dir_z = float(direction.z());
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::isfinite(tMax) ? float(tMax) : std::numeric_limits<float>::infinity();
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

bool Scene::intersect(const Ray& ray, double tMax, SurfaceHit& hit) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    if (!representable(ray.origin, ray.direction)) return false;
    RTCRayHit rh = embreeRayHit(ray.origin, ray.direction, tMax);
    rtcIntersect1(top_, &context, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;

    hit.t = rh.ray.tfar;
    // An object's id is its instance's, or its geometry's when placed as is.
    hit.object = static_cast<int>(rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID);
    hit.primitive = rh.hit.primID;
    hit.position = ray.origin + hit.t * ray.direction;
    const SceneObject& o = objects[hit.object];
    const Vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    hit.geometricNormal = (o.normalFromObject * ng).normalized();
    hit.shadingNormal = hit.geometricNormal;
    hit.objectPosition = (o.objectFromWorld * hit.position.homogeneous()).head<3>();
    hit.objectNormal = ng.normalized();
    hit.hasUv = false;
    if (o.kind == SceneObject::Kind::Mesh) {
        const TriangleMesh& mesh = *meshes[o.shape];
        const uint32_t* idx = &mesh.indices[3 * hit.primitive];
        const double u = rh.hit.u, v = rh.hit.v;
        if (!mesh.uvs.empty()) {
            auto uvOf = [&](uint32_t i) { return Eigen::Vector2d(mesh.uvs[2 * i], mesh.uvs[2 * i + 1]); };
            hit.uv = (1 - u - v) * uvOf(idx[0]) + u * uvOf(idx[1]) + v * uvOf(idx[2]);
            hit.hasUv = true;
            // The square root of the triangle's area in uv over its area in
            // object space: how far a pixel's footprint reaches in uv.
            const Eigen::Vector2d e1 = uvOf(idx[1]) - uvOf(idx[0]), e2 = uvOf(idx[2]) - uvOf(idx[0]);
            const double objectArea = (mesh.vertex(idx[1]) - mesh.vertex(idx[0])).cross(mesh.vertex(idx[2]) - mesh.vertex(idx[0])).norm();
            hit.uvPerLength = objectArea > 0 ? std::sqrt(std::abs(e1.x() * e2.y() - e1.y() * e2.x()) / objectArea) : 0.0;
        }
        if (!mesh.normals.empty()) {
            const Vec3 n = (1 - u - v) * mesh.normal(idx[0]) + u * mesh.normal(idx[1]) + v * mesh.normal(idx[2]);
            if (n.norm() > 0) {
                hit.shadingNormal = (o.normalFromObject * n).normalized();
                // Keep shading and geometric normals on the same side.
                if (hit.shadingNormal.dot(hit.geometricNormal) < 0) hit.geometricNormal = -hit.geometricNormal;
            }
        }
    }
    return true;
}

bool Scene::occluded(const Vec3& origin, const Vec3& direction, double tMax) const {
    if (!representable(origin, direction) || std::isnan(tMax)) return false;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    RTCRay r;
    r.org_x = float(origin.x());
    r.org_y = float(origin.y());
    r.org_z = float(origin.z());
    r.dir_x = float(direction.x());
    r.dir_y = float(direction.y());
    r.dir_z = float(direction.z());
    r.tnear = 0.0f;
    r.tfar = std::isfinite(tMax) ? float(tMax) : std::numeric_limits<float>::infinity();
    r.mask = 0xFFFFFFFFu;
    r.flags = 0;
    r.time = 0.0f;
    rtcOccluded1(top_, &context, &r);
    return r.tfar < 0;
}

}  // namespace isotrace
