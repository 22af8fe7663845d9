#include "renderer/microfacet_albedo.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>

#include "renderer/fresnel.h"
#include "renderer/microfacet.h"
#include "renderer/sampling/sampling.h"

namespace isotrace {

namespace {

constexpr int kStrata = 32;

// Grazing directions have no well-defined albedo at mu = 0 itself.
constexpr double kSmallestCosine = 1e-3;

Vec3 directionAt(double mu) { return Vec3(std::sqrt(std::max(0.0, 1.0 - mu * mu)), 0.0, mu); }

// Calls visit(m, weight) for strata x strata normals drawn from the
// visible-normal density seen from wo (one per stratum, at its centre),
// the weights summing to 1. The light a lobe loses comes from the normals
// tilted most, at the rim of the projected disk the sampler maps u[0] to
// (u[0] near 1): the strata there are made finer by u[0] = 1 - (1 - s)^3,
// s uniform. With 32 x 32 the albedos are then within 1.2e-3 of 512 x 512.
template <class Visit>
void forVisibleNormals(const TrowbridgeReitz& d, const Vec3& wo, int strata, Visit&& visit) {
    for (int a = 0; a < strata; ++a) {
        const double s = (a + 0.5) / strata, rest = 1.0 - s;
        const double u0 = 1.0 - rest * rest * rest, weight = 3.0 * rest * rest / (double(strata) * strata);
        for (int b = 0; b < strata; ++b) visit(d.sampleVisibleNormal(wo, Eigen::Vector2d(u0, (b + 0.5) / strata)), weight);
    }
}

}  // namespace

double MicrofacetAlbedoTable::nodeCosine(int i) {
    return std::max(kSmallestCosine, double(i) / (kCosines - 1));
}

double MicrofacetAlbedoTable::at(double mu, double roughness) const {
    const double x = std::clamp(mu, 0.0, 1.0) * (kCosines - 1), y = std::clamp(roughness, 0.0, 1.0) * (kRoughnesses - 1);
    const int i = std::min(int(x), kCosines - 2), j = std::min(int(y), kRoughnesses - 2);
    const double fx = x - i, fy = y - j;
    const double low = (1 - fx) * values_[index(i, j)] + fx * values_[index(i + 1, j)];
    const double high = (1 - fx) * values_[index(i, j + 1)] + fx * values_[index(i + 1, j + 1)];
    return (1 - fy) * low + fy * high;
}

double MicrofacetAlbedoTable::average(double roughness) const {
    const double y = std::clamp(roughness, 0.0, 1.0) * (kRoughnesses - 1);
    const int j = std::min(int(y), kRoughnesses - 2);
    const double fy = y - j;
    return (1 - fy) * averages_[j] + fy * averages_[j + 1];
}

int MicrofacetAlbedoTable::firstColumn(double lowest) {
    return std::clamp(int(std::floor(std::clamp(lowest, 0.0, 1.0) * (kRoughnesses - 1))), 0, kRoughnesses - 2);
}

int MicrofacetAlbedoTable::lastColumn(double highest) {
    return std::clamp(int(std::floor(std::clamp(highest, 0.0, 1.0) * (kRoughnesses - 1))) + 1, 1, kRoughnesses - 1);
}

void MicrofacetAlbedoTable::setColumn(int j, const std::array<double, kCosines>& values) {
    for (int i = 0; i < kCosines; ++i) values_[index(i, j)] = values[size_t(i)];
    // The average of the interpolant the lobes use (midpoint rule, fine
    // enough that its error is far below the table's). At a node's
    // roughness at() reads this column alone.
    const int cells = 512;
    double sum = 0.0;
    for (int c = 0; c < cells; ++c) {
        const double mu = (c + 0.5) / cells;
        sum += at(mu, nodeRoughness(j)) * 2.0 * mu;
    }
    averages_[size_t(j)] = sum / cells;
    filled_[size_t(j)] = true;
}

double conductorAlbedoAt(double mu, double alpha, int strata) {
    const TrowbridgeReitz d(alpha, alpha);
    const Vec3 wo = directionAt(mu);
    double sum = 0.0;
    // Sampled by visible normals, f cos / pdf is G2 / G1(wo).
    forVisibleNormals(d, wo, strata, [&](const Vec3& m, double weight) {
        const Vec3 wi = reflect(-wo, m);
        if (wi.z() > 0) sum += weight * d.G(wo, wi) / d.G1(wo);
    });
    return sum;
}

void dielectricAlbedoAt(double mu, double alpha, double eta, int strata, double& reflected, double& total) {
    const TrowbridgeReitz d(alpha, alpha);
    const Vec3 wo = directionAt(mu);
    double reflectedSum = 0.0, refractedSum = 0.0;
    forVisibleNormals(d, wo, strata, [&](const Vec3& m, double weight) {
        const double F = fresnelDielectric(wo.dot(m), eta);
        const Vec3 wr = reflect(-wo, m);
        if (wr.z() > 0) reflectedSum += weight * F * d.G(wo, wr) / d.G1(wo);
        if (F < 1.0) {
            if (const std::optional<Vec3> wt = refract(wo, m, eta); wt && wt->z() < 0)
                refractedSum += weight * (1.0 - F) * d.G(wo, *wt) / d.G1(wo);
        }
    });
    reflected = reflectedSum;
    total = reflectedSum + refractedSum;
}

namespace {

// Below the smooth limit a lobe is a delta lobe, and keeps everything.
double alphaOfNode(double roughness) { return TrowbridgeReitz::alphaFromRoughness(roughness); }
bool smoothNode(double roughness) { return alphaOfNode(roughness) < TrowbridgeReitz::kSmoothAlpha; }

}  // namespace

namespace {

// Fills the missing columns of K tables that are filled together, for
// roughness in [lowest, highest], from albedos(mu, r) (K values), in
// parallel over columns and cosines. The caller holds the tables' lock.
template <size_t K, class Albedos>
void fillColumns(const std::array<MicrofacetAlbedoTable*, K>& tables, double lowest, double highest,
                 Albedos&& albedos) {
    std::vector<int> missing;
    for (int j = MicrofacetAlbedoTable::firstColumn(lowest); j <= MicrofacetAlbedoTable::lastColumn(highest); ++j)
        if (!tables[0]->hasColumn(j)) missing.push_back(j);
    constexpr int n = MicrofacetAlbedoTable::kCosines;
    std::vector<std::array<std::array<double, n>, K>> columns(missing.size());
    tbb::parallel_for(size_t(0), missing.size() * n, [&](size_t k) {
        const size_t c = k / n, i = k % n;
        const std::array<double, K> values =
            albedos(MicrofacetAlbedoTable::nodeCosine(int(i)), MicrofacetAlbedoTable::nodeRoughness(missing[c]));
        for (size_t t = 0; t < K; ++t) columns[c][t][i] = values[t];
    });
    for (size_t c = 0; c < missing.size(); ++c)
        for (size_t t = 0; t < K; ++t) tables[t]->setColumn(missing[c], columns[c][t]);
}

std::mutex& tablesMutex() {
    static std::mutex mutex;
    return mutex;
}

}  // namespace

const MicrofacetAlbedoTable& conductorAlbedo(double lowest, double highest) {
    static MicrofacetAlbedoTable table;
    const std::lock_guard<std::mutex> lock(tablesMutex());
    fillColumns(std::array{&table}, lowest, highest, [](double mu, double r) {
        return std::array{smoothNode(r) ? 1.0 : conductorAlbedoAt(mu, alphaOfNode(r), kStrata)};
    });
    return table;
}

std::shared_ptr<const DielectricAlbedo> dielectricAlbedo(double ior, double lowest, double highest) {
    static std::map<double, std::shared_ptr<DielectricAlbedo>> computed;
    const std::lock_guard<std::mutex> lock(tablesMutex());
    std::shared_ptr<DielectricAlbedo>& albedo = computed[ior];
    if (!albedo) {
        albedo = std::make_shared<DielectricAlbedo>();
        albedo->fresnelAverageOutside = fresnelDiffuseReflectance(ior);
    }
    // Seen from outside, the reflection alone and with refraction come from
    // one integration.
    fillColumns(std::array{&albedo->reflectedOutside, &albedo->outside}, lowest, highest, [&](double mu, double r) {
        double reflected = fresnelDielectric(mu, ior), total = 1.0;
        if (!smoothNode(r)) dielectricAlbedoAt(mu, alphaOfNode(r), ior, kStrata, reflected, total);
        return std::array{reflected, total};
    });
    fillColumns(std::array{&albedo->inside}, lowest, highest, [&](double mu, double r) {
        double reflected = 0.0, total = 1.0;
        if (!smoothNode(r)) dielectricAlbedoAt(mu, alphaOfNode(r), 1.0 / ior, kStrata, reflected, total);
        return std::array{total};
    });
    return albedo;
}

}  // namespace isotrace
