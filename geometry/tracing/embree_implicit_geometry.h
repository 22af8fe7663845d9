// Registers an ImplicitSurface with Embree as user geometry: one primitive
// per surface cell, with bounds, intersect and occluded callbacks that honour
// valid masks, ray masks, [tnear, tfar], instancing and filter functions.
#pragma once

#include <embree3/rtcore.h>

#include "geometry/tracing/implicit_surface.h"

namespace isotrace::geometry {

/// Attaches `surface` to `scene` and returns its geometry id. The surface
/// must outlive the scene. Rays whose mask shares no bit with `mask` pass
/// through it (checked in the callbacks, whatever Embree's build options).
/// The geometry is committed; the scene is not.
unsigned attachImplicitSurface(RTCDevice device, RTCScene scene, ImplicitSurface& surface,
                               unsigned mask = 0xFFFFFFFFu);
/// The same under a given geometry id, with the surface's ray mask as it
/// stands (an object of a renderer's top scene, placed without an instance).
void attachImplicitSurfaceAs(RTCDevice device, RTCScene scene, ImplicitSurface& surface, unsigned id);

}  // namespace isotrace::geometry
