// `isotrace compare`: image differences with thresholds, for regression
// tests and people. Exit 0 within thresholds, 1 over the fail threshold (or
// NaN and infinite pixels), 2 for bad input.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "geometry/errors.h"
#include "renderer/commands/command.h"
#include "renderer/image/flip_metric.h"
#include "renderer/image/image_comparison.h"
#include "renderer/image/image_file.h"
#include "renderer/image/openimageio_library.h"
#include "renderer/image/image_output.h"

namespace isotrace {

namespace {

using geometry::InputError;

struct CompareCommand {
    std::string test, reference;
    std::string metric = "rmse";
    double fail = -1.0;          ///< < 0: the metric's default
    double warn = -1.0;          ///< < 0: none
    double failPercent = -1.0;   ///< < 0: none
    double pixelThreshold = 0.1;
    double pixelsPerDegree = 0.0;  ///< FLIP viewing condition; 0: the papers' default
    std::string noise;           ///< a second render of `test` with another seed
    std::string diff;            ///< difference image (.exr: |a - b|; other: a colour map)
    bool json = false;
};

// Channel names and size, checked before pixels are compared.
struct ImageShape {
    int width, height;
    std::vector<std::string> channels;
    bool floatingPoint;  ///< linear HDR data (EXR, HDR, float TIFF) rather than display-encoded values
};

// Image readers name the file in their messages; InputError names it once.
InputError imageError(const std::string& path, const std::exception& e) {
    std::string message = e.what();
    if (message.rfind(path + ": ", 0) == 0) message.erase(0, path.size() + 2);
    return InputError(path, "", message);
}

ImageShape shapeOf(const std::string& path) {
    try {
        const ImageFile file = readImageFile(path, false);
        return {file.width, file.height, file.channelNames, file.floatingPoint};
    } catch (const std::exception& e) {
        throw imageError(path, e);
    }
}

// Display-encoded files (PNG, JPEG, 8/16-bit TIFF) hold sRGB values; FLIP
// works on linear ones.
Image linearized(Image image) {
    for (float& v : image.rgb) v = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
    return image;
}

// The FLIP error map: .exr holds the errors, other formats the magma colour
// map of the FLIP papers.
void writeFlipMap(const std::string& path, const FlipResult& flip) {
    Image map;
    map.width = flip.width;
    map.height = flip.height;
    map.rgb.resize(flip.errors.size() * 3);
    for (size_t i = 0; i < flip.errors.size(); ++i) map.rgb[3 * i] = map.rgb[3 * i + 1] = map.rgb[3 * i + 2] = flip.errors[i];
    if (std::filesystem::path(path).extension() == ".exr") {
        writeImage(path, map, {}, false);
        return;
    }
    // The colour map's output is display-encoded already; writePreviewPng
    // encodes linear values, so undo that here.
    try {
        map.rgb = openImageIo().colorMap(flip.errors, flip.width, flip.height, "magma");
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(path + ": " + e.what());
    }
    writePreviewPng(path, linearized(map), 0.0);
}

std::string joined(const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ",") + n;
    return s;
}

Image load(const std::string& path) {
    try {
        return readImage(path);
    } catch (const std::exception& e) {
        throw imageError(path, e);
    }
}

void writeDifference(const std::string& path, const Image& a, const Image& b) {
    Image d = b;
    d.x = d.y = 0;
    d.fullWidth = d.fullHeight = 0;
    double largest = 0;
    for (size_t i = 0; i < d.rgb.size(); ++i) {
        d.rgb[i] = std::abs(a.rgb[i] - b.rgb[i]);
        if (std::isfinite(d.rgb[i])) largest = std::max(largest, double(d.rgb[i]));
    }
    std::string extension = std::filesystem::path(path).extension().string();
    if (extension == ".exr") {
        writeImage(path, d, {}, false);
        return;
    }
    // A colour map of the largest channel difference: black, red, yellow, white.
    for (size_t p = 0; p < d.rgb.size() / 3; ++p) {
        const double m = std::max({d.rgb[3 * p], d.rgb[3 * p + 1], d.rgb[3 * p + 2]});
        const double t = largest > 0 ? std::clamp(m / largest, 0.0, 1.0) : 0.0;
        d.rgb[3 * p] = float(std::clamp(3 * t, 0.0, 1.0));
        d.rgb[3 * p + 1] = float(std::clamp(3 * t - 1, 0.0, 1.0));
        d.rgb[3 * p + 2] = float(std::clamp(3 * t - 2, 0.0, 1.0));
        if (!std::isfinite(m)) d.rgb[3 * p] = d.rgb[3 * p + 2] = 1.0f, d.rgb[3 * p + 1] = 0.0f;  // magenta
    }
    writePreviewPng(path, d, 0.0);
}


int runCompare(const CompareCommand& c) {
    const ImageShape a = shapeOf(c.test), b = shapeOf(c.reference);
    if (a.width != b.width || a.height != b.height)
        throw InputError(c.test, "", "size " + std::to_string(a.width) + "x" + std::to_string(a.height) + " differs from " +
                                         c.reference + "'s " + std::to_string(b.width) + "x" + std::to_string(b.height));
    if (a.channels != b.channels)
        throw InputError(c.test, "", "channels " + joined(a.channels) + " differ from " + c.reference + "'s " +
                                         joined(b.channels));
    if (!c.diff.empty()) {
        std::vector<std::string> inputs{c.test, c.reference};
        if (!c.noise.empty()) inputs.push_back(c.noise);
        checkOutputPath(c.diff, inputs);
    }
    if (c.metric == "noise" && c.noise.empty())
        throw InputError("command line", "", "--metric noise needs --noise, a second render of the test image");
    const Image test = load(c.test), reference = load(c.reference);
    const ImageDifference d = compareImages(test, reference, c.pixelThreshold);

    double noiseScore = std::nan("");
    if (!c.noise.empty()) {
        const ImageShape n = shapeOf(c.noise);
        if (n.width != a.width || n.height != a.height)
            throw InputError(c.noise, "", "size differs from " + c.test + "'s");
        noiseScore = isotrace::noiseScore(test, reference, load(c.noise));
    }

    const bool flipMetric = c.metric.rfind("flip", 0) == 0;
    FlipResult flip;
    bool hdr = false;
    if (flipMetric) {
        hdr = c.metric == "flip-hdr" || (c.metric == "flip" && (a.floatingPoint || b.floatingPoint));
        const Image t = a.floatingPoint ? test : linearized(test), r = b.floatingPoint ? reference : linearized(reference);
        const double ppd = c.pixelsPerDegree > 0 ? c.pixelsPerDegree : defaultPixelsPerDegree();
        flip = hdr ? hdrFlip(t, r, ppd) : ldrFlip(t, r, ppd);
    }

    const double value = flipMetric             ? flip.mean
                         : c.metric == "rmse"   ? d.rmse
                         : c.metric == "relmse" ? d.relativeMse
                         : c.metric == "psnr"   ? d.psnr
                         : c.metric == "max"    ? d.maxAbsolute
                         : c.metric == "mean"   ? d.meanAbsolute
                         : c.metric == "over"   ? d.fractionOver
                                                : noiseScore;
    // Thresholds: tiny by default (identical images pass); 3 for noise
    // scores, which measure 0.3 to 1.6 for renders differing only by seed and
    // above 5 for a visible change (tests/renderer/command_line_test.cpp);
    // a mean FLIP of 0.05, below which differences are hard to spot when
    // flipping between the images.
    const double failAt = c.fail >= 0              ? c.fail
                          : c.metric == "noise"    ? 3.0
                          : c.metric == "psnr"     ? 60.0
                          : flipMetric             ? 0.05
                                                   : 1e-6;
    auto worse = [&](double threshold) { return c.metric == "psnr" ? value < threshold : value > threshold; };
    bool failed = worse(failAt) || d.nonFinite > 0;
    if (c.failPercent >= 0 && 100.0 * d.fractionOver > c.failPercent) failed = true;
    const bool warned = !failed && c.warn >= 0 && worse(c.warn);
    const std::string verdict = failed ? "FAIL" : warned ? "WARN" : "PASS";

    if (!c.diff.empty()) {
        if (flipMetric)
            writeFlipMap(c.diff, flip);
        else
            writeDifference(c.diff, test, reference);
    }
    if (c.json) {
        nlohmann::json j = {{"rmse", d.rmse},
                            {"relmse", d.relativeMse},
                            {"psnr", std::isinf(d.psnr) ? nlohmann::json("inf") : nlohmann::json(d.psnr)},
                            {"max", d.maxAbsolute},
                            {"mean", d.meanAbsolute},
                            {"over", d.fractionOver},
                            {"non_finite_pixels", d.nonFinite},
                            {"metric", c.metric},
                            {"value", std::isinf(value) ? nlohmann::json("inf") : nlohmann::json(value)},
                            {"fail_threshold", failAt},
                            {"verdict", verdict}};
        if (!c.noise.empty()) j["noise"] = noiseScore;
        if (flipMetric) {
            j["flip"] = {{"mean", flip.mean}, {"variant", hdr ? "hdr" : "ldr"}};
            if (hdr)
                j["flip"].update({{"start_exposure", flip.startExposure},
                                  {"stop_exposure", flip.stopExposure},
                                  {"exposures", flip.exposures}});
        }
        if (d.nonFinite) j["first_non_finite_pixel"] = {d.firstNonFiniteX, d.firstNonFiniteY};
        std::printf("%s\n", j.dump(2).c_str());
    } else {
        std::printf("rmse %.6g  relmse %.6g  psnr %.4g dB  max %.6g  mean %.6g  differing pixels %.3f%%\n", d.rmse,
                    d.relativeMse, d.psnr, d.maxAbsolute, d.meanAbsolute, 100.0 * d.fractionOver);
        if (!c.noise.empty()) std::printf("noise score %.4g (about 1 for differences within noise)\n", noiseScore);
        if (flipMetric && hdr)
            std::printf("HDR-FLIP %.6g over %d exposures from %.3g to %.3g stops\n", flip.mean, flip.exposures,
                        flip.startExposure, flip.stopExposure);
        else if (flipMetric)
            std::printf("LDR-FLIP %.6g\n", flip.mean);
        if (d.nonFinite)
            std::printf("%lld pixels are NaN or infinite; the first at (%d, %d)\n", d.nonFinite, d.firstNonFiniteX,
                        d.firstNonFiniteY);
        if (d.nonFinite > 0 && !worse(failAt))
            // The metrics cover the finite pixels only: the verdict must not
            // read as if a small value failed.
            std::printf("FAIL: %lld pixels are NaN or infinite (%s %.6g over the finite ones)\n", d.nonFinite,
                        c.metric.c_str(), value);
        else
            std::printf("%s: %s %.6g (fail at %.6g)\n", verdict.c_str(), c.metric.c_str(), value, failAt);
    }
    return failed ? kExitComparisonFailed : kExitSuccess;
}

}  // namespace

Subcommand addCompareCommand(CLI::App& app) {
    auto c = std::make_shared<CompareCommand>();
    CLI::App* cmd = app.add_subcommand("compare", "Compare two images (EXR, PNG, HDR, TIFF, ...) with thresholds");
    cmd->add_option("test", c->test, "The image to judge")->required();
    cmd->add_option("reference", c->reference, "The reference image")->required();
    cmd->add_option("--metric", c->metric,
                    "rmse, relmse, psnr, max, mean, over (fraction of differing pixels), noise, flip (mean FLIP: HDR-FLIP "
                    "for floating-point files, LDR-FLIP otherwise), flip-ldr, flip-hdr")
        ->check(CLI::IsMember({"rmse", "relmse", "psnr", "max", "mean", "over", "noise", "flip", "flip-ldr", "flip-hdr"}));
    cmd->add_option("--ppd", c->pixelsPerDegree,
                    "FLIP viewing condition: pixels per degree of visual angle (default 67: a 0.7 m wide 4K monitor at 0.7 m)")
        ->check(CLI::Range(1.0, 1000.0));
    cmd->add_option("--fail", c->fail, "Fail (exit 1) when the metric is worse than this (psnr: lower)")
        ->check(finiteNumber());
    cmd->add_option("--warn", c->warn, "Warn when the metric is worse than this")->check(finiteNumber());
    cmd->add_option("--fail-percent", c->failPercent, "Fail when more than this percentage of pixels differ")
        ->check(CLI::Range(0.0, 100.0));
    cmd->add_option("--pixel-threshold", c->pixelThreshold,
                    "A pixel differs when |a - b| > threshold * (|b| + 0.05) in some channel")
        ->check(finitePositive());
    cmd->add_option("--noise", c->noise, "A second render of TEST with another seed: judge differences against noise");
    cmd->add_option("--diff", c->diff,
                    "Write a difference image: .exr holds |a - b| (FLIP metrics: the FLIP errors), other formats a colour "
                    "map (FLIP: magma)");
    cmd->add_flag("--json", c->json, "Print the metrics as JSON");
    return {cmd, [c] { return runCompare(*c); }};
}

}  // namespace isotrace
