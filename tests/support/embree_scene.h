// A bare Embree scene holding implicit surfaces, for geometry tests that
// exercise the user-geometry callbacks exactly as a host would.
#pragma once

#include <embree3/rtcore.h>

#include <limits>

#include "geometry/tracing/embree_implicit_geometry.h"

namespace isotrace::testing {

struct EmbreeHit {
    bool hit = false;
    double t = 0.0;
    geometry::Vec3 normal;
    unsigned geomID = RTC_INVALID_GEOMETRY_ID, instID = RTC_INVALID_GEOMETRY_ID, primID = 0;
};

class EmbreeScene {
public:
    explicit EmbreeScene(RTCSceneFlags flags = RTC_SCENE_FLAG_NONE) {
        device_ = rtcNewDevice(nullptr);
        scene_ = rtcNewScene(device_);
        rtcSetSceneFlags(scene_, flags);
    }
    ~EmbreeScene() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    RTCDevice device() const { return device_; }
    RTCScene scene() const { return scene_; }
    unsigned attach(geometry::ImplicitSurface& surface, unsigned mask = 0xFFFFFFFFu) {
        return geometry::attachImplicitSurface(device_, scene_, surface, mask);
    }
    void commit() { rtcCommitScene(scene_); }

    static RTCRayHit makeRay(const geometry::Vec3& o, const geometry::Vec3& d, double tNear = 0.0,
                             double tFar = std::numeric_limits<double>::infinity(), unsigned mask = 0xFFFFFFFFu) {
        RTCRayHit rh{};
        rh.ray.org_x = float(o.x());
        rh.ray.org_y = float(o.y());
        rh.ray.org_z = float(o.z());
        rh.ray.dir_x = float(d.x());
        rh.ray.dir_y = float(d.y());
        rh.ray.dir_z = float(d.z());
        rh.ray.tnear = float(tNear);
        rh.ray.tfar = float(tFar);
        rh.ray.mask = mask;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        return rh;
    }

    EmbreeHit intersect(const geometry::Vec3& o, const geometry::Vec3& d, double tNear = 0.0,
                        double tFar = std::numeric_limits<double>::infinity(), unsigned mask = 0xFFFFFFFFu,
                        RTCIntersectContext* context = nullptr) const {
        RTCIntersectContext own;
        if (!context) {
            rtcInitIntersectContext(&own);
            context = &own;
        }
        RTCRayHit rh = makeRay(o, d, tNear, tFar, mask);
        rtcIntersect1(scene_, context, &rh);
        EmbreeHit h;
        h.hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        if (h.hit) {
            h.t = rh.ray.tfar;
            h.normal = geometry::Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
            h.geomID = rh.hit.geomID;
            h.instID = rh.hit.instID[0];
            h.primID = rh.hit.primID;
        }
        return h;
    }

    bool occluded(const geometry::Vec3& o, const geometry::Vec3& d, double tFar) const {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh = makeRay(o, d, 0.0, tFar);
        rtcOccluded1(scene_, &context, &rh.ray);
        return rh.ray.tfar < 0;
    }

private:
    RTCDevice device_;
    RTCScene scene_;
};

}  // namespace isotrace::testing
