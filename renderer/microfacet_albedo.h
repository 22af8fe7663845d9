// How much light single-scattering GGX lobes keep, for energy
// compensation (Kulla and Conty 2017). A single-scattering microfacet
// lobe drops the light that bounces between facets before it leaves: 10%
// of it for a white metal at roughness 1. The directional albedo E(mu) of
// the lobe, and its average 2 int E(mu) mu dmu, say how much is missing;
// materials add it back as a second, reciprocal lobe
// (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)).
//
// Tables are over the cosine mu of the angle to the normal and the
// perceptual roughness r (alpha = r^2), integrated over visible normals
// (stratified, 32 x 32 per entry). Only the roughness columns a material
// can reach are integrated, when it is made, in parallel, and kept for the
// next: the conductor's table is shared, a dielectric's is one per index.
#pragma once

#include <array>
#include <memory>

namespace isotrace {

class MicrofacetAlbedoTable {
public:
    static constexpr int kCosines = 32, kRoughnesses = 32;

    /// E at cosine mu in [0, 1] and roughness r in [0, 1], bilinear.
    double at(double mu, double roughness) const;
    /// 2 int_0^1 E(mu) mu dmu at roughness r.
    double average(double roughness) const;

    static double nodeCosine(int i);
    static double nodeRoughness(int j) { return double(j) / (kRoughnesses - 1); }
    /// The columns at() reads for roughness in [lowest, highest].
    static int firstColumn(double lowest);
    static int lastColumn(double highest);
    bool hasColumn(int j) const { return filled_[size_t(j)]; }
    /// Sets column j from its albedos at the nodes, in order of cosine.
    void setColumn(int j, const std::array<double, kCosines>& values);

private:
    static int index(int i, int j) { return j * kCosines + i; }

    std::array<double, kCosines * kRoughnesses> values_{};
    std::array<double, kRoughnesses> averages_{};
    std::array<bool, kRoughnesses> filled_{};
};

/// A conductor lobe's albedo with Fresnel reflectance 1, valid for
/// roughness in [lowest, highest].
const MicrofacetAlbedoTable& conductorAlbedo(double lowest, double highest);

/// A rough dielectric interface of index `ior` (inside over outside). Light
/// refracted counts as energy: its 1 / eta^2 radiance scaling is undone.
struct DielectricAlbedo {
    MicrofacetAlbedoTable reflectedOutside;  ///< the reflection alone, seen from outside (a coat)
    MicrofacetAlbedoTable outside;           ///< reflection and refraction, from outside
    MicrofacetAlbedoTable inside;            ///< reflection and refraction, from inside
    double fresnelAverageOutside = 0.0;      ///< 2 int F(mu) mu dmu of the smooth interface, from outside
};

/// Shared between the materials of one index, valid for roughness in
/// [lowest, highest].
std::shared_ptr<const DielectricAlbedo> dielectricAlbedo(double ior, double lowest, double highest);

/// The single-scattering lobes' albedos at one node, by the same
/// integration the tables use (for tests, with more strata).
double conductorAlbedoAt(double mu, double alpha, int strata);
/// Reflected and total (reflected plus refracted) energy of a rough
/// interface of relative index eta (behind over front) seen at cosine mu.
void dielectricAlbedoAt(double mu, double alpha, double eta, int strata, double& reflected, double& total);

}  // namespace isotrace
