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
/// lookups between texel centres.
///
/// Directions are sampled in proportion to that bilinear radiance. The
/// cells of the sampling grid lie between texel centres, where the lookup
/// is one bilinear patch of four texels; a cell is chosen by its patch's
/// mean luminance times its solid angle, and a direction within it from the
/// patch itself (sampleBilinear), taken across the cell in azimuth and in
/// cos theta, so that the density is the patch's over the cell's solid
/// angle. A sharp-edged sun is then sampled as the lookup ramps it off; a
/// density constant per texel left a ramp's samples weights from half to
/// twice their mean, and uniform in theta it grew as 1 / sin theta towards
/// the zenith, where a high sun sits.
class EnvironmentMapLight final : public Light {
public:
    EnvironmentMapLight(std::vector<float> texels, int width, int height, double scale, const Mat3& worldFromMap)
        : texels_(std::move(texels)), width_(width), height_(height), scale_(scale),
          worldFromMap_(worldFromMap), mapFromWorld_(worldFromMap.transpose()) {
        double meanLuminance = 0.0, solidAngle = 0.0;
        mean_ = RGB::Zero();
        for (int y = 0; y < height; ++y) {
            const double rowSolidAngle = 2.0 * std::numbers::pi / width *
                                         (std::cos(std::numbers::pi * y / height) - std::cos(std::numbers::pi * (y + 1) / height));
            for (int x = 0; x < width; ++x) {
                const RGB c = texel(x, y);
                mean_ += c * rowSolidAngle;
                meanLuminance += luminance(c) * rowSolidAngle;
                solidAngle += rowSolidAngle;
            }
        }
        mean_ *= scale_ / solidAngle;
        meanLuminance_ = scale_ * meanLuminance / solidAngle;
        // Cell (i, j): from texel centre column i to i + 1 (wrapping), from
        // texel centre row j - 1 to j (rows -1 and height being the poles).
        cellEdgeCosines_.resize(size_t(height) + 2);
        cellEdgeCosines_.front() = 1.0;
        cellEdgeCosines_.back() = -1.0;
        for (int j = 1; j <= height; ++j) cellEdgeCosines_[size_t(j)] = std::cos(std::numbers::pi * (j - 0.5) / height);
        std::vector<double> weights(size_t(width) * (height + 1));
        for (int j = 0; j <= height; ++j) {
            const double cellSolidAngle = cosAtCellEdge(j) - cosAtCellEdge(j + 1);
            for (int i = 0; i < width; ++i) {
                const Corners c = corners(i, j);
                weights[size_t(j) * width + i] = 0.25 * (c.a00 + c.a10 + c.a01 + c.a11) * cellSolidAngle;
            }
        }
        distribution_ = PiecewiseConstant2D(weights, width, height + 1);
    }

    bool isInfinite() const override { return true; }

    LightSample sample(const LightSampleContext& context, const Eigen::Vector2d& u) const override {
        LightSample s;
        double pdfCells = 0.0;
        const Eigen::Vector2d cell = distribution_.sample(u, pdfCells);
        s.distance = std::numeric_limits<double>::infinity();
        if (!(pdfCells > 0)) return s;
        // The place within the chosen cell is uniform: it drives the patch.
        const double cx = cell.x() * width_, cy = cell.y() * (height_ + 1);
        const int i = std::min(int(cx), width_ - 1), j = std::min(int(cy), height_);
        const Corners c = corners(i, j);
        const Eigen::Vector2d p = sampleBilinear({cx - i, cy - j}, c.a00, c.a10, c.a01, c.a11);
        const double top = cosAtCellEdge(j), bottom = cosAtCellEdge(j + 1);
        const double cosTheta = std::clamp(top + p.y() * (bottom - top), -1.0, 1.0);
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
        const double phi = 2.0 * std::numbers::pi * ((i + 0.5 + p.x()) / width_ - 0.5);
        s.direction = worldFromMap_ * Vec3(sinTheta * std::sin(phi), cosTheta, -sinTheta * std::cos(phi));
        s.pdf = density(pdfCells, i, j, p, c);
        s.radiance = escapedRadiance(s.direction);
        return s;
    }
    double pdf(const LightSampleContext&, const Vec3& wi, const Vec3&, const Vec3&) const override {
        const Vec3 d = (mapFromWorld_ * wi).normalized();
        const double cosTheta = std::clamp(d.y(), -1.0, 1.0);
        const double v = std::acos(cosTheta) / std::numbers::pi;
        const int j = std::clamp(int(std::floor(v * height_ + 0.5)), 0, height_);
        const double top = cosAtCellEdge(j), bottom = cosAtCellEdge(j + 1);
        double x = (std::atan2(d.x(), -d.z()) / (2.0 * std::numbers::pi) + 0.5) * width_ - 0.5;
        x -= std::floor(x / width_) * width_;  // into [0, width): cell columns wrap
        const int i = std::min(int(x), width_ - 1);
        const Eigen::Vector2d p(std::clamp(x - i, 0.0, 1.0),
                                top > bottom ? std::clamp((top - cosTheta) / (top - bottom), 0.0, 1.0) : 0.5);
        const double pdfCells = distribution_.pdf({(i + 0.5) / width_, (j + 0.5) / (height_ + 1)});
        return density(pdfCells, i, j, p, corners(i, j));
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
    struct Corners {
        double a00, a10, a01, a11;  ///< luminance at (column, row) offsets (0 or 1, 0 or 1)
    };
    RGB texel(int x, int y) const {
        const float* t = &texels_[3 * (size_t(y) * width_ + x)];
        return RGB(t[0], t[1], t[2]);
    }
    /// The four texels of cell (i, j)'s patch (clamped rows at the poles).
    Corners corners(int i, int j) const {
        const int x0 = i, x1 = (i + 1) % width_;
        const int y0 = std::max(j - 1, 0), y1 = std::min(j, height_ - 1);
        // From the texels themselves: the radiance lookup reads the same
        // cache lines.
        auto at = [&](int x, int y) { return luminance(texel(x, y)); };
        return {at(x0, y0), at(x1, y0), at(x0, y1), at(x1, y1)};
    }
    /// cos theta at the top edge of cell row j (0 to height + 1): the
    /// pole, a texel centre, the other pole.
    double cosAtCellEdge(int j) const { return cellEdgeCosines_[size_t(j)]; }
    /// The density in solid angle at place p of cell (i, j), whose cell
    /// density over the unit square is pdfCells: the cell's probability,
    /// spread over its solid angle as its patch is.
    double density(double pdfCells, int i, int j, const Eigen::Vector2d& p, const Corners& c) const {
        const double cellSolidAngle = 2.0 * std::numbers::pi / width_ * (cosAtCellEdge(j) - cosAtCellEdge(j + 1));
        if (!(pdfCells > 0) || !(cellSolidAngle > 0)) return 0.0;
        const double probability = pdfCells / (double(width_) * (height_ + 1));
        return probability * bilinearPdf(p, c.a00, c.a10, c.a01, c.a11) / cellSolidAngle;
    }
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
    std::vector<double> cellEdgeCosines_;
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
