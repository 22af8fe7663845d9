// Embree, loaded when rays are to be traced.
//
// Linked in, Embree cost every start of the executable about 5 ms before
// main (43 MB of library, 168 static constructors, 15,600 relocations, 200
// page faults at some 20 us each on a virtual machine): half of `isotrace
// --version`, and all of it wasted for the commands that trace no rays. The
// executable does not link it (see renderer/CMakeLists.txt). It defines
// instead the Embree functions the program calls, each a call through a
// pointer to the library's own, and loads the library with dlopen: in the
// background from the start of the commands that trace rays, while they
// parse the command line and the scene and build fields, or else on the
// first call. (On 2 cores a render gains nothing measurable from the
// overlap: the load's CPU time has to be spent somewhere.)
//
// Every Embree object comes from a device, so only rtcNewDevice waits for
// the library; the others call through pointers set before it returned,
// and the per-ray calls cost one indirect call more, no lock.
#include "renderer/commands/embree_on_demand.h"

#include <dlfcn.h>
#include <embree3/rtcore.h>
#include <tbb/task_arena.h>

#include <cstdlib>
#include <future>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

namespace isotrace {

namespace {

#define ISOTRACE_EMBREE_FUNCTIONS(X)                                                                               \
    X(rtcNewDevice) X(rtcReleaseDevice) X(rtcSetDeviceErrorFunction) X(rtcNewScene) X(rtcReleaseScene)             \
    X(rtcCommitScene) X(rtcGetSceneBounds) X(rtcIntersect1) X(rtcOccluded1) X(rtcNewGeometry)                      \
    X(rtcReleaseGeometry) X(rtcCommitGeometry) X(rtcAttachGeometry) X(rtcAttachGeometryByID)                       \
    X(rtcSetSharedGeometryBuffer) X(rtcSetGeometryTransform) X(rtcSetGeometryInstancedScene)                       \
    X(rtcSetGeometryUserPrimitiveCount) X(rtcSetGeometryUserData) X(rtcSetGeometryBoundsFunction)                  \
    X(rtcSetGeometryIntersectFunction) X(rtcSetGeometryOccludedFunction) X(rtcSetGeometryMask)                     \
    X(rtcFilterIntersection) X(rtcFilterOcclusion)

struct EmbreeFunctions {
#define ISOTRACE_EMBREE_POINTER(name) decltype(&::name) name = nullptr;
    ISOTRACE_EMBREE_FUNCTIONS(ISOTRACE_EMBREE_POINTER)
#undef ISOTRACE_EMBREE_POINTER
};

EmbreeFunctions embree;

// The file ISOTRACE_EMBREE_LIBRARY names, or else Embree 3 by its soname
// (wherever the dynamic loader finds it: Debian's libembree-dev) and then
// where CMake found it at configure time (an Embree built elsewhere).
void* openEmbree(std::string& file) {
    const char* named = std::getenv("ISOTRACE_EMBREE_LIBRARY");
    std::vector<std::string> candidates;
    if (named && *named) candidates = {named};
    else candidates = {"libembree3.so.3", ISOTRACE_EMBREE_CONFIGURED_FILE};
    std::string reasons;
    for (const std::string& candidate : candidates) {
        if (void* library = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL)) {
            file = candidate;
            return library;
        }
        const char* reason = dlerror();
        reasons += (reasons.empty() ? "" : "; ") + std::string(reason ? reason : candidate + ": unknown error");
    }
    throw std::runtime_error("cannot load Embree (" + candidates.front() + "), which tracing rays needs: " + reasons);
}

void loadEmbree() {
    std::string file;
    void* library = openEmbree(file);
    EmbreeFunctions found;
#define ISOTRACE_EMBREE_RESOLVE(name)                                                                      \
    found.name = reinterpret_cast<decltype(&::name)>(dlsym(library, #name));                               \
    if (!found.name) throw std::runtime_error(file + " is not Embree 3: it lacks " #name);
    ISOTRACE_EMBREE_FUNCTIONS(ISOTRACE_EMBREE_RESOLVE)
#undef ISOTRACE_EMBREE_RESOLVE
    embree = found;
}

// The load, started once; its future rethrows a failure to every waiter.
std::once_flag started;
std::shared_future<void> loading;

void startLoading() {
    std::call_once(started, [] { loading = std::async(std::launch::async, loadEmbree).share(); });
}

}  // namespace

void finishLoadingEmbree() {
    if (!loading.valid()) return;
    try {
        loading.get();
    } catch (const std::exception&) {
        // Reported to whoever needed Embree; nothing is left to do here.
    }
}

void startLoadingEmbree() {
    // TBB first: its start-up loads a library too (tbbmalloc), and a load
    // waits for any other to finish, static constructors and all. Begun
    // after Embree's, it held the scene's loading back by 2 to 4 ms.
    tbb::task_arena arena;
    arena.initialize();
    startLoading();
}

}  // namespace isotrace

using isotrace::embree;

extern "C" {

RTCDevice rtcNewDevice(const char* config) {
    isotrace::startLoading();
    isotrace::loading.get();
    return embree.rtcNewDevice(config);
}
void rtcReleaseDevice(RTCDevice device) { embree.rtcReleaseDevice(device); }
void rtcSetDeviceErrorFunction(RTCDevice device, RTCErrorFunction error, void* userPtr) {
    embree.rtcSetDeviceErrorFunction(device, error, userPtr);
}
RTCScene rtcNewScene(RTCDevice device) { return embree.rtcNewScene(device); }
void rtcReleaseScene(RTCScene scene) { embree.rtcReleaseScene(scene); }
void rtcCommitScene(RTCScene scene) { embree.rtcCommitScene(scene); }
void rtcGetSceneBounds(RTCScene scene, RTCBounds* bounds) { embree.rtcGetSceneBounds(scene, bounds); }
void rtcIntersect1(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
    embree.rtcIntersect1(scene, context, rayhit);
}
void rtcOccluded1(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
    embree.rtcOccluded1(scene, context, ray);
}
RTCGeometry rtcNewGeometry(RTCDevice device, RTCGeometryType type) { return embree.rtcNewGeometry(device, type); }
void rtcReleaseGeometry(RTCGeometry geometry) { embree.rtcReleaseGeometry(geometry); }
void rtcCommitGeometry(RTCGeometry geometry) { embree.rtcCommitGeometry(geometry); }
unsigned int rtcAttachGeometry(RTCScene scene, RTCGeometry geometry) {
    return embree.rtcAttachGeometry(scene, geometry);
}
void rtcAttachGeometryByID(RTCScene scene, RTCGeometry geometry, unsigned int geomID) {
    embree.rtcAttachGeometryByID(scene, geometry, geomID);
}
void rtcSetSharedGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot, RTCFormat format,
                                const void* ptr, size_t byteOffset, size_t byteStride, size_t itemCount) {
    embree.rtcSetSharedGeometryBuffer(geometry, type, slot, format, ptr, byteOffset, byteStride, itemCount);
}
void rtcSetGeometryTransform(RTCGeometry geometry, unsigned int timeStep, RTCFormat format, const void* xfm) {
    embree.rtcSetGeometryTransform(geometry, timeStep, format, xfm);
}
void rtcSetGeometryInstancedScene(RTCGeometry geometry, RTCScene scene) {
    embree.rtcSetGeometryInstancedScene(geometry, scene);
}
void rtcSetGeometryUserPrimitiveCount(RTCGeometry geometry, unsigned int userPrimitiveCount) {
    embree.rtcSetGeometryUserPrimitiveCount(geometry, userPrimitiveCount);
}
void rtcSetGeometryUserData(RTCGeometry geometry, void* ptr) { embree.rtcSetGeometryUserData(geometry, ptr); }
void rtcSetGeometryBoundsFunction(RTCGeometry geometry, RTCBoundsFunction bounds, void* userPtr) {
    embree.rtcSetGeometryBoundsFunction(geometry, bounds, userPtr);
}
void rtcSetGeometryIntersectFunction(RTCGeometry geometry, RTCIntersectFunctionN intersect) {
    embree.rtcSetGeometryIntersectFunction(geometry, intersect);
}
void rtcSetGeometryOccludedFunction(RTCGeometry geometry, RTCOccludedFunctionN occluded) {
    embree.rtcSetGeometryOccludedFunction(geometry, occluded);
}
void rtcSetGeometryMask(RTCGeometry geometry, unsigned int mask) { embree.rtcSetGeometryMask(geometry, mask); }
void rtcFilterIntersection(const RTCIntersectFunctionNArguments* args, const RTCFilterFunctionNArguments* filterArgs) {
    embree.rtcFilterIntersection(args, filterArgs);
}
void rtcFilterOcclusion(const RTCOccludedFunctionNArguments* args, const RTCFilterFunctionNArguments* filterArgs) {
    embree.rtcFilterOcclusion(args, filterArgs);
}

}  // extern "C"
