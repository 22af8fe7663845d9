// Soak test: renders of random valid scenes, one after another in one
// process, with the resident memory after each. Memory that grows from the
// first renders to the last is a leak (or a cache without bound).
//
//   soak [renders]     (default 200)
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>

#include "renderer/render.h"
#include "renderer/scene_loader.h"

using namespace isotrace;

namespace {

double residentMegabytes() {
    std::ifstream statm("/proc/self/statm");
    long pages = 0, resident = 0;
    statm >> pages >> resident;
    return double(resident) * double(sysconf(_SC_PAGESIZE)) / (1 << 20);
}

// A random scene: a few primitives, CSG and blobs, with random materials of
// every kind, lit by random lights, some objects polygonized or as particles.
geometry::Json randomScene(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    auto colour = [&] { return geometry::Json::array({u(rng), u(rng), u(rng)}); };
    const char* materialTypes[] = {"diffuse", "mirror", "conductor", "dielectric", "plastic"};
    geometry::Json materials = geometry::Json::object();
    for (int i = 0; i < 4; ++i) {
        const std::string type = materialTypes[rng() % 5];
        geometry::Json m = {{"type", type}};
        if (type == "diffuse" || type == "plastic") m["albedo"] = colour();
        if (type == "conductor" || type == "dielectric" || type == "plastic") m["roughness"] = u(rng) < 0.5 ? 0.0 : u(rng);
        if (type == "diffuse" && u(rng) < 0.3) m["albedo"] = {{"type", "checker"}, {"scale", 0.3}, {"colors", {colour(), colour()}}};
        materials["m" + std::to_string(i)] = m;
    }
    geometry::Json fields = {
        {"ball", {{"type", "sphere"}, {"radius", 0.5 + u(rng)}}},
        {"ring", {{"type", "torus"}, {"major", 0.8}, {"minor", 0.1 + 0.3 * u(rng)}}},
        {"cut", {{"type", "difference"}, {"of", {"ball", "ring"}}}},
        {"blob", {{"type", "blobby"}, {"kernel", "soft"}, {"threshold", 0.3},
                  {"blobs", {{{"center", {0, 0, 0}}, {"radius", 1.0}}, {{"center", {0.6 * u(rng), 0.3, 0}}, {"radius", 0.8}}}}}},
    };
    const char* names[] = {"ball", "ring", "cut", "blob"};
    const char* as[] = {"implicit", "implicit", "mesh", "particles"};
    geometry::Json objects = geometry::Json::array();
    const int count = 1 + int(rng() % 4);
    for (int i = 0; i < count; ++i) {
        geometry::Json o = {{"field", names[rng() % 4]}, {"material", "m" + std::to_string(rng() % 4)},
                            {"transform", {{"translate", {3 * u(rng) - 1.5, u(rng), 3 * u(rng) - 1.5}}}}};
        const std::string a = as[rng() % 4];
        o["as"] = a;
        if (a == "mesh") o["resolution"] = 24;
        if (a == "particles") o["count"] = 300;
        objects.push_back(o);
    }
    objects.push_back({{"vertices", {-9, -1, -9, 9, -1, -9, 9, -1, 9, -9, -1, 9}}, {"indices", {0, 2, 1, 0, 3, 2}}, {"material", "m0"}});
    geometry::Json lights = geometry::Json::array({{{"type", "environment"}, {"radiance", colour()}}});
    if (u(rng) < 0.5) lights.push_back({{"type", "point"}, {"position", {0, 4, 2}}, {"intensity", {20, 20, 20}}});
    if (u(rng) < 0.5)
        lights.push_back({{"type", "quad"}, {"corner", {-1, 4, -1}}, {"edge1", {2, 0, 0}}, {"edge2", {0, 0, 2}}, {"radiance", {5, 5, 5}}});
    return {{"camera", {{"from", {0, 2, 6}}, {"to", {0, 0, 0}}}},
            {"film", {{"width", 32}, {"height", 24}, {"spp", 4}}},
            {"integrator", {{"type", u(rng) < 0.8 ? "path" : "whitted"}}},
            {"materials", materials},
            {"fields", fields},
            {"objects", objects},
            {"lights", lights}};
}

}  // namespace

int main(int argc, char** argv) {
    const int renders = argc > 1 ? std::atoi(argv[1]) : 200;
    std::mt19937 rng(12345);
    std::vector<double> resident;
    for (int i = 0; i < renders; ++i) {
        const auto scene = loadSceneDescription(randomScene(rng), "/tmp/soak.json");
        RenderOptions options;
        options.threads = 2;
        options.seed = uint64_t(i);
        options.quiet = true;
        render(*scene, options);
        resident.push_back(residentMegabytes());
    }
    auto mean = [&](int from, int to) {
        double sum = 0;
        for (int i = from; i < to; ++i) sum += resident[i];
        return sum / (to - from);
    };
    const int window = std::max(1, renders / 10);
    std::printf("%d random scenes rendered; resident memory: first %d renders %.1f MB, last %d %.1f MB, peak %.1f MB\n",
                renders, window, mean(0, window), window, mean(renders - window, renders),
                *std::max_element(resident.begin(), resident.end()));
}
