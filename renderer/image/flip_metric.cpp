#include "renderer/image/flip_metric.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <tbb/parallel_for.h>

namespace isotrace {

namespace {

using std::numbers::pi;

// One channel of an image.
struct Plane {
    int width = 0, height = 0;
    std::vector<float> v;
    Plane(int w, int h) : width(w), height(h), v(size_t(w) * h, 0.0f) {}
    float& at(int x, int y) { return v[size_t(y) * width + x]; }
    float at(int x, int y) const { return v[size_t(y) * width + x]; }
};

// A 1D kernel with taps -radius..radius.
using Kernel = std::vector<double>;

// Convolves rows with `horizontal`, then columns with `vertical`, repeating
// the edge pixels outside the image (as the reference implementation does).
Plane separableFilter(const Plane& in, const Kernel& horizontal, const Kernel& vertical) {
    const int rx = int(horizontal.size() / 2), ry = int(vertical.size() / 2);
    Plane rows(in.width, in.height), out(in.width, in.height);
    tbb::parallel_for(0, in.height, [&](int y) {
        for (int x = 0; x < in.width; ++x) {
            double s = 0;
            for (int k = -rx; k <= rx; ++k) s += horizontal[k + rx] * in.at(std::clamp(x + k, 0, in.width - 1), y);
            rows.at(x, y) = float(s);
        }
    });
    tbb::parallel_for(0, in.height, [&](int y) {
        for (int x = 0; x < in.width; ++x) {
            double s = 0;
            for (int k = -ry; k <= ry; ++k) s += vertical[k + ry] * rows.at(x, std::clamp(y + k, 0, in.height - 1));
            out.at(x, y) = float(s);
        }
    });
    return out;
}

Kernel normalized(Kernel k) {
    double sum = 0;
    for (double w : k) sum += w;
    for (double& w : k) w /= sum;
    return k;
}

// Scales positive taps to sum to 1 and negative taps to -1, so flat regions
// give exactly zero response.
Kernel balanced(Kernel k) {
    double positive = 0, negative = 0;
    for (double w : k) (w > 0 ? positive : negative) += w;
    for (double& w : k) w = w > 0 ? w / positive : w < 0 ? w / -negative : 0.0;
    return k;
}

// The sRGB (D65) primaries: linear RGB to CIE XYZ.
const Eigen::Matrix3d& rgbToXyz() {
    static const Eigen::Matrix3d m = [] {
        Eigen::Matrix3d a;
        a << 10135552.0 / 24577794, 8788810.0 / 24577794, 4435075.0 / 24577794,  //
            2613072.0 / 12288897, 8788810.0 / 12288897, 887015.0 / 12288897,     //
            1425312.0 / 73733382, 8788810.0 / 73733382, 70074185.0 / 73733382;
        return a;
    }();
    return m;
}
const Eigen::Matrix3d& xyzToRgb() {
    static const Eigen::Matrix3d m = rgbToXyz().inverse();
    return m;
}
// The reference white (D65) is XYZ of RGB (1, 1, 1).
const Eigen::Vector3d& whitePoint() {
    static const Eigen::Vector3d w = rgbToXyz() * Eigen::Vector3d::Ones();
    return w;
}

Eigen::Vector3d linearRgbToYcxcz(const Eigen::Vector3d& rgb) {
    const Eigen::Vector3d xyz = (rgbToXyz() * rgb).cwiseQuotient(whitePoint());
    return {116.0 * xyz.y() - 16.0, 500.0 * (xyz.x() - xyz.y()), 200.0 * (xyz.y() - xyz.z())};
}

Eigen::Vector3d ycxczToLinearRgb(const Eigen::Vector3d& c) {
    const double y = (c.x() + 16.0) / 116.0;
    const Eigen::Vector3d xyz(y + c.y() / 500.0, y, y - c.z() / 200.0);
    return xyzToRgb() * xyz.cwiseProduct(whitePoint());
}

// CIELAB with the Hunt adjustment (chroma scaled by L/100: colours fade in
// the dark).
Eigen::Vector3d huntAdjustedLab(const Eigen::Vector3d& rgb) {
    Eigen::Vector3d xyz = (rgbToXyz() * rgb).cwiseQuotient(whitePoint());
    constexpr double delta = 6.0 / 29.0;
    for (int i = 0; i < 3; ++i)
        xyz[i] = xyz[i] > delta * delta * delta ? std::cbrt(xyz[i]) : xyz[i] / (3 * delta * delta) + 4.0 / 29.0;
    const double l = 116.0 * xyz.y() - 16.0;
    return {l, 0.01 * l * 500.0 * (xyz.x() - xyz.y()), 0.01 * l * 200.0 * (xyz.y() - xyz.z())};
}

// HyAB: city-block in lightness, Euclidean in chroma (suits large differences).
double hyab(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::abs(a.x() - b.x()) + std::hypot(a.y() - b.y(), a.z() - b.z());
}

constexpr double kColorExponent = 0.7;    // q_c
constexpr double kFeatureExponent = 0.5;  // q_f
constexpr double kRedistributeKnee = 0.4; // p_c
constexpr double kRedistributeTo = 0.95;  // p_t

// The spatial contrast sensitivity of the achromatic, red-green and
// blue-yellow channels, each a sum of (at most two) Gaussians
// a sqrt(pi / b) exp(-pi^2 r^2 / b) with r in degrees.
struct ContrastSensitivity {
    double a1, b1, a2, b2;
};
constexpr ContrastSensitivity kChannelSensitivity[3] = {
    {1.0, 0.0047, 0.0, 1e-5}, {1.0, 0.0053, 0.0, 1e-5}, {34.1, 0.04, 13.5, 0.025}};

// Filters one opponent channel with its sensitivity. Each Gaussian term is
// separable; the weights normalise the 2D sum to one.
Plane contrastFilter(const Plane& in, const ContrastSensitivity& s, double ppd) {
    constexpr double widestB = 0.04;
    const int radius = int(std::ceil(3.0 * std::sqrt(widestB / (2 * pi * pi)) * ppd));
    auto gaussian = [&](double b) {
        Kernel k(2 * radius + 1);
        for (int i = -radius; i <= radius; ++i) k[i + radius] = std::exp(-pi * pi * (i / ppd) * (i / ppd) / b);
        return k;
    };
    const Kernel g1 = gaussian(s.b1), g2 = gaussian(s.b2);
    double sum1 = 0, sum2 = 0;
    for (int i = 0; i <= 2 * radius; ++i) sum1 += g1[i], sum2 += g2[i];
    const double w1 = s.a1 * std::sqrt(pi / s.b1) * sum1 * sum1, w2 = s.a2 * std::sqrt(pi / s.b2) * sum2 * sum2;
    Plane out = separableFilter(in, normalized(g1), normalized(g1));
    if (w2 > 0) {
        const Plane second = separableFilter(in, normalized(g2), normalized(g2));
        for (size_t i = 0; i < out.v.size(); ++i) out.v[i] = float((w1 * out.v[i] + w2 * second.v[i]) / (w1 + w2));
    }
    return out;
}

// Gradient magnitude ("edge") or second-derivative magnitude ("point") of the
// normalised lightness, at the scale of human edge detection (0.082 degrees
// peak to trough).
Plane featureMagnitude(const Plane& lightness, double ppd, bool points) {
    const double sd = 0.5 * 0.082 * ppd;
    const int radius = int(std::ceil(3.0 * sd));
    Kernel g(2 * radius + 1), d(2 * radius + 1);
    for (int i = -radius; i <= radius; ++i) {
        g[i + radius] = std::exp(-double(i) * i / (2 * sd * sd));
        d[i + radius] = points ? (double(i) * i / (sd * sd) - 1.0) * g[i + radius] : -i * g[i + radius];
    }
    const Kernel smooth = normalized(g), derivative = balanced(d);
    const Plane fx = separableFilter(lightness, derivative, smooth);
    const Plane fy = separableFilter(lightness, smooth, derivative);
    Plane out(lightness.width, lightness.height);
    for (size_t i = 0; i < out.v.size(); ++i) out.v[i] = std::hypot(fx.v[i], fy.v[i]);
    return out;
}

// The per-pixel colour of an image in linear RGB clamped to [0, 1], as
// opponent planes (Y, Cx, Cz).
std::array<Plane, 3> opponentPlanes(const std::vector<float>& rgb, int width, int height) {
    std::array<Plane, 3> planes{Plane(width, height), Plane(width, height), Plane(width, height)};
    for (size_t p = 0; p < size_t(width) * height; ++p) {
        Eigen::Vector3d c(rgb[3 * p], rgb[3 * p + 1], rgb[3 * p + 2]);
        for (int i = 0; i < 3; ++i) c[i] = std::isfinite(c[i]) ? std::clamp(c[i], 0.0, 1.0) : 0.0;
        const Eigen::Vector3d o = linearRgbToYcxcz(c);
        for (int i = 0; i < 3; ++i) planes[i].v[p] = float(o[i]);
    }
    return planes;
}

// LDR-FLIP of linear RGB buffers (clamped to [0, 1]).
std::vector<float> flipErrors(const std::vector<float>& test, const std::vector<float>& reference, int width,
                              int height, double ppd) {
    struct Prepared {
        std::vector<Eigen::Vector3d> lab;  // filtered, Hunt-adjusted
        Plane edges, points;
    };
    auto prepare = [&](const std::vector<float>& rgb) {
        const std::array<Plane, 3> opponent = opponentPlanes(rgb, width, height);
        std::array<Plane, 3> filtered{contrastFilter(opponent[0], kChannelSensitivity[0], ppd),
                                      contrastFilter(opponent[1], kChannelSensitivity[1], ppd),
                                      contrastFilter(opponent[2], kChannelSensitivity[2], ppd)};
        Prepared p{std::vector<Eigen::Vector3d>(size_t(width) * height), Plane(width, height), Plane(width, height)};
        Plane lightness(width, height);
        for (size_t i = 0; i < p.lab.size(); ++i) {
            const Eigen::Vector3d c(filtered[0].v[i], filtered[1].v[i], filtered[2].v[i]);
            p.lab[i] = huntAdjustedLab(ycxczToLinearRgb(c).cwiseMax(0.0).cwiseMin(1.0));
            lightness.v[i] = (opponent[0].v[i] + 16.0f) / 116.0f;
        }
        p.edges = featureMagnitude(lightness, ppd, false);
        p.points = featureMagnitude(lightness, ppd, true);
        return p;
    };
    const Prepared t = prepare(test), r = prepare(reference);

    // The largest colour difference: between pure green and pure blue.
    static const double maxColorError = std::pow(
        hyab(huntAdjustedLab(Eigen::Vector3d(0, 1, 0)), huntAdjustedLab(Eigen::Vector3d(0, 0, 1))), kColorExponent);
    const double knee = kRedistributeKnee * maxColorError;
    std::vector<float> errors(size_t(width) * height);
    for (size_t i = 0; i < errors.size(); ++i) {
        const double c = std::pow(hyab(t.lab[i], r.lab[i]), kColorExponent);
        const double colorError = c < knee ? kRedistributeTo / knee * c
                                           : kRedistributeTo + (c - knee) / (maxColorError - knee) * (1.0 - kRedistributeTo);
        const double feature = std::max(std::abs(t.edges.v[i] - r.edges.v[i]), std::abs(t.points.v[i] - r.points.v[i]));
        const double featureError = std::pow(feature / std::sqrt(2.0), kFeatureExponent);
        errors[i] = float(std::pow(colorError, 1.0 - featureError));
    }
    return errors;
}

void checkSizes(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height)
        throw std::invalid_argument("image sizes differ: " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                                    " against " + std::to_string(b.width) + "x" + std::to_string(b.height));
}

double meanOf(const std::vector<float>& v) {
    double sum = 0;
    for (float x : v) sum += x;
    return v.empty() ? 0.0 : sum / double(v.size());
}

// The ACES filmic curve fit (Narkowicz) with its 0.6 pre-exposure folded in:
// (k0 x^2 + k1 x) / (k3 x^2 + k4 x + k5).
constexpr double kAces[5] = {0.6 * 0.6 * 2.51, 0.6 * 0.03, 0.6 * 0.6 * 2.43, 0.6 * 0.59, 0.14};

double acesToneMap(double x) {
    const double value = (kAces[0] * x * x + kAces[1] * x) / (kAces[2] * x * x + kAces[3] * x + kAces[4]);
    return std::isfinite(value) ? std::clamp(value, 0.0, 1.0) : 1.0;
}

// The input that the curve maps to `t`: the positive root of
// (k0 - k2 t) x^2 + (k1 - k3 t) x - k4 t = 0.
double acesInverse(double t) {
    const double a = kAces[0] - kAces[2] * t, b = kAces[1] - kAces[3] * t, c = -kAces[4] * t;
    return (-b + std::sqrt(b * b - 4 * a * c)) / (2 * a);
}

}  // namespace

double pixelsPerDegree(double distanceMeters, double widthMeters, double pixelsX) {
    return distanceMeters * (pixelsX / widthMeters) * pi / 180.0;
}

FlipResult ldrFlip(const Image& test, const Image& reference, double ppd) {
    checkSizes(test, reference);
    FlipResult r;
    r.width = test.width;
    r.height = test.height;
    r.errors = flipErrors(test.rgb, reference.rgb, test.width, test.height, ppd);
    r.mean = meanOf(r.errors);
    return r;
}

FlipResult hdrFlip(const Image& test, const Image& reference, double ppd) {
    checkSizes(test, reference);
    FlipResult r;
    r.width = test.width;
    r.height = test.height;

    std::vector<double> luminance;
    luminance.reserve(size_t(reference.width) * reference.height);
    for (size_t p = 0; p < reference.rgb.size() / 3; ++p) {
        const double y = 0.2126 * reference.rgb[3 * p] + 0.7152 * reference.rgb[3 * p + 1] + 0.0722 * reference.rgb[3 * p + 2];
        luminance.push_back(std::isfinite(y) ? std::max(y, 0.0) : 0.0);
    }
    const double brightest = luminance.empty() ? 0.0 : *std::max_element(luminance.begin(), luminance.end());
    if (brightest > 0) {
        // The median over every pixel, black ones included, as NVIDIA's
        // reference does. Only when more than half the image is black
        // (where the reference's stop exposure is infinite) the median of the
        // lit pixels stands in.
        std::vector<double> all = luminance;
        std::nth_element(all.begin(), all.begin() + all.size() / 2, all.end());
        double median = all[all.size() / 2];
        if (!(median > 0)) {
            std::vector<double> lit;
            for (double y : luminance)
                if (y > 0) lit.push_back(y);
            std::nth_element(lit.begin(), lit.begin() + lit.size() / 2, lit.end());
            median = lit[lit.size() / 2];
        }
        const double target = acesInverse(0.85);
        r.startExposure = std::log2(target / brightest);
        r.stopExposure = std::log2(target / median);
    }
    r.exposures = std::max(2, int(std::ceil(r.stopExposure - r.startExposure)));
    const double step = (r.stopExposure - r.startExposure) / (r.exposures - 1);

    r.errors.assign(size_t(r.width) * r.height, 0.0f);
    std::vector<float> t(test.rgb.size()), ref(reference.rgb.size());
    for (int e = 0; e < r.exposures; ++e) {
        const double scale = std::exp2(r.startExposure + e * step);
        for (size_t i = 0; i < t.size(); ++i) {
            t[i] = float(acesToneMap(std::max(0.0, double(test.rgb[i])) * scale));
            ref[i] = float(acesToneMap(std::max(0.0, double(reference.rgb[i])) * scale));
        }
        const std::vector<float> errors = flipErrors(t, ref, r.width, r.height, ppd);
        for (size_t i = 0; i < errors.size(); ++i) r.errors[i] = std::max(r.errors[i], errors[i]);
    }
    r.mean = meanOf(r.errors);
    return r;
}

}  // namespace isotrace
