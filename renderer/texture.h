// Textures: values that vary over a surface, for any colour or roughness
// parameter of a material. Implicit surfaces have no UVs, so every texture
// is a function of the point in the object's own space (and its normal):
// solid textures, triplanar image projection, and ramps driven by a field.
// Each type is one file in textures/, listed in textures/texture_types.cpp.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "renderer/bsdf.h"
#include "renderer/registry.h"

namespace isotrace::geometry {
class FieldLibrary;
}

namespace isotrace {

class Texture {
public:
    virtual ~Texture() = default;
    /// The value at a shading point (thread-safe, allocation-free).
    virtual RGB evaluate(const ShadingPoint& p) const = 0;
    /// 1 for grey values, 3 for colours.
    virtual int channels() const = 0;
    /// Bounds of every channel over all points (for validating parameters).
    virtual RGB minimum() const = 0;
    virtual RGB maximum() const = 0;
};

/// What material and texture factories may resolve besides their own keys.
struct MaterialContext {
    /// Relative file names (image textures) are relative to this folder.
    std::filesystem::path directory;
    /// The scene's fields, for textures driven by a field; null when the
    /// scene has none.
    const geometry::FieldLibrary* fields = nullptr;
};

/// Reads one texture's keys (the reader is left for the caller to finish).
using TextureFactory = std::shared_ptr<const Texture> (*)(geometry::JsonObjectReader& r, const MaterialContext& context);
const Registry<TextureFactory>& textureRegistry();

/// A colour that is either constant or a texture.
class ColorParameter {
public:
    ColorParameter() = default;
    explicit ColorParameter(const RGB& value) : constant_(value) {}
    explicit ColorParameter(std::shared_ptr<const Texture> texture) : texture_(std::move(texture)) {}

    RGB at(const ShadingPoint& p) const { return texture_ ? texture_->evaluate(p) : constant_; }
    RGB maximum() const { return texture_ ? texture_->maximum() : constant_; }
    RGB minimum() const { return texture_ ? texture_->minimum() : constant_; }

private:
    RGB constant_ = RGB::Zero();
    std::shared_ptr<const Texture> texture_;
};

/// A scalar that is either constant or a one-channel texture.
class ScalarParameter {
public:
    ScalarParameter() = default;
    explicit ScalarParameter(double value) : constant_(value) {}
    explicit ScalarParameter(std::shared_ptr<const Texture> texture) : texture_(std::move(texture)) {}

    double at(const ShadingPoint& p) const { return texture_ ? texture_->evaluate(p)[0] : constant_; }
    double maximum() const { return texture_ ? texture_->maximum()[0] : constant_; }
    double minimum() const { return texture_ ? texture_->minimum()[0] : constant_; }

private:
    double constant_ = 0.0;
    std::shared_ptr<const Texture> texture_;
};

/// A colour at `key`: an RGB triple, or a texture object ({"type": ...}).
/// Fails when any value it can take lies outside [lowest, highest].
ColorParameter readColorParameter(geometry::JsonObjectReader& r, const std::string& key, const RGB& fallback,
                                  const MaterialContext& context, double lowest = 0.0, double highest = INFINITY);
/// A number at `key`, or a one-channel texture object; values must lie in
/// [lowest, highest].
ScalarParameter readScalarParameter(geometry::JsonObjectReader& r, const std::string& key, double fallback,
                                    const MaterialContext& context, double lowest, double highest);

}  // namespace isotrace

namespace isotrace {

// Helpers for texture factories.

/// A texture value in a file: a number (grey, 1 channel) or an RGB triple
/// (3 channels); channels is set accordingly.
RGB readTextureValue(const geometry::Json& j, const std::string& pointer, const std::string& file, int& channels);

/// Piecewise-linear map from a number to a value, constant beyond its ends.
class ValueRamp {
public:
    struct Stop {
        double position;
        RGB value;
    };
    /// Reads [[position, value], ...] with increasing positions.
    static ValueRamp read(geometry::JsonObjectReader& r, const std::string& key);
    RGB at(double x) const;
    int channels() const { return channels_; }
    RGB minimum() const;
    RGB maximum() const;

private:
    std::vector<Stop> stops_;
    int channels_ = 1;
};

}  // namespace isotrace
