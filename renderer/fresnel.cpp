#include "renderer/fresnel.h"

#include <algorithm>
#include <cmath>
#include <complex>

namespace isotrace {

double fresnelDielectric(double cosThetaI, double eta) {
    cosThetaI = std::clamp(cosThetaI, -1.0, 1.0);
    if (cosThetaI < 0) {  // arriving from behind: swap the media
        eta = 1.0 / eta;
        cosThetaI = -cosThetaI;
    }
    const double sin2ThetaT = (1.0 - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= 1.0) return 1.0;
    const double cosThetaT = std::sqrt(1.0 - sin2ThetaT);
    const double rParallel = (eta * cosThetaI - cosThetaT) / (eta * cosThetaI + cosThetaT);
    const double rPerpendicular = (cosThetaI - eta * cosThetaT) / (cosThetaI + eta * cosThetaT);
    return 0.5 * (rParallel * rParallel + rPerpendicular * rPerpendicular);
}

RGB fresnelConductor(double cosThetaI, const RGB& eta, const RGB& k) {
    cosThetaI = std::clamp(std::abs(cosThetaI), 0.0, 1.0);
    RGB result;
    for (int c = 0; c < 3; ++c) {
        const std::complex<double> n(eta[c], k[c]);
        const std::complex<double> sin2ThetaT = (1.0 - cosThetaI * cosThetaI) / (n * n);
        const std::complex<double> cosThetaT = std::sqrt(1.0 - sin2ThetaT);
        const std::complex<double> rParallel = (n * cosThetaI - cosThetaT) / (n * cosThetaI + cosThetaT);
        const std::complex<double> rPerpendicular = (cosThetaI - n * cosThetaT) / (cosThetaI + n * cosThetaT);
        result[c] = 0.5 * (std::norm(rParallel) + std::norm(rPerpendicular));
    }
    return result;
}

double fresnelDiffuseReflectance(double eta) {
    // Midpoint rule in cos theta; 65536 cells put the error near 1e-8 even
    // with the kink at the critical angle (about a millisecond, once per material).
    const int cells = 1 << 16;
    double sum = 0.0;
    for (int i = 0; i < cells; ++i) {
        const double mu = (i + 0.5) / cells;
        sum += fresnelDielectric(mu, eta) * 2.0 * mu;
    }
    return sum / cells;
}

std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, double eta) {
    const double cosThetaI = n.dot(wi);
    const double sin2ThetaT = std::max(0.0, 1.0 - cosThetaI * cosThetaI) / (eta * eta);
    if (sin2ThetaT >= 1.0) return std::nullopt;
    const double cosThetaT = std::sqrt(1.0 - sin2ThetaT);
    return Vec3(-wi / eta + (cosThetaI / eta - cosThetaT) * n);
}

}  // namespace isotrace
