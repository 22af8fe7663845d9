// "environment": radiance from every direction around the scene, constant
// ("radiance") or from a latitude-longitude map ("file"). At most one per
// scene.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <vector>

#include "renderer/image/image_file.h"
#include "renderer/light.h"
#include "renderer/scene_builder.h"
#include "renderer/sampling/piecewise_constant.h"
#include "renderer/sampling/sampling.h"
#include "renderer/scene_values.h"

namespace isotrace {

namespace {

class EnvironmentLight final : public Light {
public:
    explicit EnvironmentLight(const RGB& radiance) : radiance_(radiance) {}

    bool isInfinite() const override { return true; }
    /// From a surface: cosine-weighted over the hemisphere it sees, the
    /// density that makes a constant environment's estimate exact for a
    /// Lambertian surface. From a point in space: uniform over the sphere.
    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const override {
        LightSample s;
        s.direction = context.n.isZero() ? sampleUniformSphere(u) : sampleCosineHemisphere(context.n, u);
        s.distance = std::numeric_limits<double>::infinity();
        s.radiance = radiance_;
        s.pdf = pdf(context, s.direction, {}, {});
        return s;
    }
    double pdf(const LightSampleContext& context, const Vec3& wi, const Vec3&, const Vec3&) const override {
        if (context.n.isZero()) return 1.0 / (4.0 * std::numbers::pi);
        const double cosTheta = context.n.dot(wi);
        return cosTheta > 0 ? cosTheta / std::numbers::pi : 0.0;
    }
    RGB escapedRadiance(const Vec3&) const override { return radiance_; }
    RGB meanRadiance() const override { return radiance_; }
    /// Irradiance pi L on a surface (4 pi L of fluence at a point in space).
    double importance(const LightSampleContext& context) const override {
        return luminance(radiance_) * (context.n.isZero() ? 4.0 : 1.0) * std::numbers::pi;
    }

private:
    RGB radiance_;
};

/// A latitude-longitude map: column u at azimuth phi = 2 pi (u - 1/2) with
/// u = 1/2 straight ahead along -z (what the default camera looks at) and
/// +x at u = 3/4; row v at polar angle theta = pi v from +y. Bilinear
/// lookups; directions are sampled by texel luminance (the brightest of a
/// texel's neighbourhood) times sin theta (a texel's solid angle), with the
/// density converted to solid angle.
class EnvironmentMapLight final : public Light {
public:
    EnvironmentMapLight(std::vector<float> texels, int width, int height, double scale, const Mat3& worldFromMap)
        : texels_(std::move(texels)), width_(width), height_(height), scale_(scale),
          worldFromMap_(worldFromMap), mapFromWorld_(worldFromMap.transpose()) {
        std::vector<double> weights(size_t(width) * height);
        double meanLuminance = 0.0, solidAngle = 0.0;
        mean_ = RGB::Zero();
        auto luminanceAt = [&](int x, int y) {
            x = ((x % width) + width) % width;
            y = std::clamp(y, 0, height - 1);
            const float* t = &texels_[3 * (size_t(y) * width + x)];
            return luminance(RGB(t[0], t[1], t[2]));
        };
        for (int y = 0; y < height; ++y) {
            const double sinTheta = std::sin(std::numbers::pi * (y + 0.5) / height);
            for (int x = 0; x < width; ++x) {
                const float* t = &texels_[3 * (size_t(y) * width + x)];
                const RGB c(t[0], t[1], t[2]);
                // Bilinear lookups reach half a texel into the neighbours:
                // weigh a texel by the brightest around it, so every direction
                // that receives light can be sampled (no fireflies left to
                // BSDF sampling at a bright texel's edge).
                double brightest = 0.0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) brightest = std::max(brightest, luminanceAt(x + dx, y + dy));
                weights[size_t(y) * width + x] = brightest * sinTheta;
                mean_ += c * sinTheta;
                meanLuminance += luminance(c) * sinTheta;
                solidAngle += sinTheta;
            }
        }
        mean_ *= scale_ / solidAngle;
        meanLuminance_ = scale_ * meanLuminance / solidAngle;
        distribution_ = PiecewiseConstant2D(weights, width, height);
    }

    bool isInfinite() const override { return true; }

    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const override {
        LightSample s;
        double pdfUV = 0.0;
        const Eigen::Vector2d uv = distribution_.sample(u, pdfUV);
        const double theta = std::numbers::pi * uv.y(), phi = 2.0 * std::numbers::pi * (uv.x() - 0.5);
        const double sinTheta = std::sin(theta);
        s.distance = std::numeric_limits<double>::infinity();
        if (!(pdfUV > 0) || !(sinTheta > 0)) return s;
        s.direction = worldFromMap_ * Vec3(sinTheta * std::sin(phi), std::cos(theta), -sinTheta * std::cos(phi));
        s.pdf = pdfUV / (2.0 * std::numbers::pi * std::numbers::pi * sinTheta);
        s.radiance = escapedRadiance(s.direction);
        return s;
    }
    double pdf(const LightSampleContext&, const Vec3& wi, const Vec3&, const Vec3&) const override {
        const Eigen::Vector2d uv = mapCoordinates(wi);
        const double sinTheta = std::sin(std::numbers::pi * uv.y());
        return sinTheta > 0 ? distribution_.pdf(uv) / (2.0 * std::numbers::pi * std::numbers::pi * sinTheta) : 0.0;
    }
    RGB escapedRadiance(const Vec3& w) const override {
        // Bilinear between texel centres: wrapping around in u, clamped in v.
        const Eigen::Vector2d uv = mapCoordinates(w);
        const double fx = uv.x() * width_ - 0.5, fy = std::clamp(uv.y() * height_ - 0.5, 0.0, height_ - 1.0);
        const int x0 = int(std::floor(fx)), y0 = int(fy);
        const double tx = fx - x0, ty = fy - y0;
        const int y1 = std::min(y0 + 1, height_ - 1);
        auto texel = [&](int x, int y) {
            x = ((x % width_) + width_) % width_;
            const float* t = &texels_[3 * (size_t(y) * width_ + x)];
            return RGB(t[0], t[1], t[2]);
        };
        const RGB c = (1 - ty) * ((1 - tx) * texel(x0, y0) + tx * texel(x0 + 1, y0)) +
                      ty * ((1 - tx) * texel(x0, y1) + tx * texel(x0 + 1, y1));
        return scale_ * c;
    }
    RGB meanRadiance() const override { return mean_; }
    double importance(const LightSampleContext& context) const override {
        return meanLuminance_ * (context.n.isZero() ? 4.0 : 1.0) * std::numbers::pi;
    }

private:
    Eigen::Vector2d mapCoordinates(const Vec3& world) const {
        const Vec3 d = (mapFromWorld_ * world).normalized();
        const double theta = std::acos(std::clamp(d.y(), -1.0, 1.0));
        double u = std::atan2(d.x(), -d.z()) / (2.0 * std::numbers::pi) + 0.5;
        if (u >= 1.0) u -= 1.0;
        return {std::clamp(u, 0.0, std::nextafter(1.0, 0.0)), std::clamp(theta / std::numbers::pi, 0.0, std::nextafter(1.0, 0.0))};
    }

    std::vector<float> texels_;  ///< RGB, row-major
    int width_, height_;
    double scale_;
    Mat3 worldFromMap_, mapFromWorld_;
    PiecewiseConstant2D distribution_;
    RGB mean_ = RGB::Zero();
    double meanLuminance_ = 0.0;
};

// The map of "file": a 2:1 latitude-longitude image of finite, non-negative
// texels; errors name the file and the key.
std::vector<float> readEnvironmentMap(geometry::JsonObjectReader& r, const std::string& path, int& width, int& height) {
    auto fail = [&](const std::string& message) { r.fail("file", "\"" + path + "\": " + message); };
    // The header first: the size is checked before any pixel is read.
    ImageFile image;
    try {
        image = readImageFile(path, false);
    } catch (const std::exception& e) {
        fail(std::string("cannot read the environment map (") + e.what() + ")");
    }
    width = image.width;
    height = image.height;
    if (width != 2 * height || height < 1)
        fail("a latitude-longitude map is twice as wide as it is high, this one is " + std::to_string(width) + "x" +
             std::to_string(height));
    if (double(width) * height > double(1 << 26)) fail("the map is too large (more than 64 Mpixels)");
    const int channels = image.channels();
    // Two channels are grey and alpha, or two colours: neither is radiance.
    if (channels != 1 && channels != 3 && channels != 4)
        fail("an environment map has 1 (grey), 3 (RGB) or 4 (RGBA) channels, this one has " + std::to_string(channels));
    try {
        image = readImageFile(path, true);
    } catch (const std::exception& e) {
        fail(std::string("cannot read the environment map (") + e.what() + ")");
    }
    const std::vector<float>& all = image.pixels;
    std::vector<float> rgb(size_t(width) * height * 3);
    for (size_t p = 0; p < size_t(width) * height; ++p)
        for (int c = 0; c < 3; ++c) {
            const float v = all[p * channels + std::min(c, channels - 1)];
            if (!std::isfinite(v) || v < 0)
                fail("texel (" + std::to_string(p % width) + ", " + std::to_string(p / width) + ") is " +
                     (std::isfinite(v) ? "negative" : "not finite") + ": radiance must be finite and >= 0");
            rgb[p * 3 + c] = v;
        }
    return rgb;
}

}  // namespace

void readEnvironmentLight(geometry::JsonObjectReader& r, SceneBuilder& builder, size_t) {
    if (builder.hasEnvironment()) r.failHere("only one environment light is allowed");
    if (!r.has("file")) {
        builder.setEnvironment(std::make_unique<EnvironmentLight>(readColor(r, "radiance", RGB::Ones())));
        return;
    }
    if (r.has("radiance")) r.fail("radiance", "give either \"radiance\" (a constant) or \"file\" (a map), not both");
    std::filesystem::path path(r.string("file"));
    if (path.is_relative()) path = std::filesystem::path(r.file()).parent_path() / path;
    const double scale = r.has("scale") ? r.number("scale") : 1.0;
    if (!(scale >= 0) || !std::isfinite(scale)) r.fail("scale", "must be a finite number >= 0");
    Mat3 rotation = Mat3::Identity();
    if (r.has("rotate")) {
        geometry::JsonObjectReader rotate = r.object("rotate");
        const Vec3 axis = rotate.vec3("axis");
        if (!(axis.norm() > 0)) rotate.fail("axis", "must not be the zero vector");
        const double angle = rotate.number("angle");
        if (!std::isfinite(angle)) rotate.fail("angle", "must be a finite number of degrees");
        rotate.finish();
        rotation = Eigen::AngleAxisd(angle * std::numbers::pi / 180.0, axis.normalized()).toRotationMatrix();
    }
    int width = 0, height = 0;
    std::vector<float> texels = readEnvironmentMap(r, path.string(), width, height);
    builder.setEnvironment(std::make_unique<EnvironmentMapLight>(std::move(texels), width, height, scale, rotation));
}

}  // namespace isotrace
