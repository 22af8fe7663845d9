#include "renderer/texture.h"

#include <algorithm>
#include <cmath>

namespace isotrace {

using geometry::InputError;
using geometry::Json;
using geometry::JsonObjectReader;
using geometry::jsonPointerAppend;

namespace {

std::shared_ptr<const Texture> readTexture(JsonObjectReader& r, const std::string& key, const MaterialContext& context) {
    JsonObjectReader t = r.object(key);
    const TextureFactory make = textureRegistry().factoryFor(t);
    std::shared_ptr<const Texture> texture = make(t, context);
    t.finish();
    return texture;
}

std::string describe(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    return text;
}

}  // namespace

ColorParameter readColorParameter(JsonObjectReader& r, const std::string& key, const RGB& fallback,
                                  const MaterialContext& context, double lowest, double highest) {
    const Json* j = r.optionalValue(key);
    if (!j) return ColorParameter(fallback);
    ColorParameter parameter;
    if (j->is_object()) {
        parameter = ColorParameter(readTexture(r, key, context));
    } else {
        const RGB value = JsonObjectReader::asVec3(*j, r.pointerOf(key), r.file()).array();
        parameter = ColorParameter(value);
    }
    if ((parameter.minimum() < lowest).any())
        r.fail(key, parameter.minimum().minCoeff() < 0 ? "colour components must not be negative"
                                                       : "values must be at least " + describe(lowest));
    if ((parameter.maximum() > highest).any())
        r.fail(key, "values must be at most " + describe(highest) + (highest == 1.0 ? " (above 1 creates energy)" : ""));
    return parameter;
}

ScalarParameter readScalarParameter(JsonObjectReader& r, const std::string& key, double fallback,
                                    const MaterialContext& context, double lowest, double highest) {
    const Json* j = r.optionalValue(key);
    if (!j) return ScalarParameter(fallback);
    ScalarParameter parameter;
    if (j->is_object()) {
        std::shared_ptr<const Texture> texture = readTexture(r, key, context);
        if (texture->channels() != 1) {
            const Json* file = j->contains("file") ? &j->at("file") : nullptr;
            r.fail(key, "a texture for a number must have one channel; " +
                            (file && file->is_string() ? "the image \"" + file->get<std::string>() + "\"" : std::string("this one")) +
                            " has " + std::to_string(texture->channels()));
        }
        parameter = ScalarParameter(std::move(texture));
    } else {
        parameter = ScalarParameter(JsonObjectReader::asNumber(*j, r.pointerOf(key), r.file()));
    }
    if (!(parameter.minimum() >= lowest && parameter.maximum() <= highest))
        r.fail(key, "must lie in [" + describe(lowest) + ", " + describe(highest) + "]");
    return parameter;
}

RGB readTextureValue(const Json& j, const std::string& pointer, const std::string& file, int& channels) {
    if (j.is_number()) {
        channels = 1;
        return RGB::Constant(JsonObjectReader::asNumber(j, pointer, file));
    }
    if (!j.is_array()) throw InputError(file, pointer, "expected a number (grey) or an RGB triple");
    channels = 3;
    return JsonObjectReader::asVec3(j, pointer, file).array();
}

ValueRamp ValueRamp::read(JsonObjectReader& r, const std::string& key) {
    const Json& j = r.value(key);
    const std::string pointer = r.pointerOf(key);
    if (!j.is_array() || j.size() < 2)
        r.fail(key, "expected at least two stops [position, value]");
    ValueRamp ramp;
    bool grey = true;
    for (size_t i = 0; i < j.size(); ++i) {
        const std::string sp = jsonPointerAppend(pointer, i);
        if (!j[i].is_array() || j[i].size() != 2) throw InputError(r.file(), sp, "expected a stop [position, value]");
        Stop s;
        s.position = JsonObjectReader::asNumber(j[i][0], sp + "/0", r.file());
        int channels = 1;
        s.value = readTextureValue(j[i][1], sp + "/1", r.file(), channels);
        grey = grey && channels == 1;
        if (!ramp.stops_.empty() && !(s.position > ramp.stops_.back().position))
            throw InputError(r.file(), sp + "/0", "stop positions must increase");
        ramp.stops_.push_back(s);
    }
    ramp.channels_ = grey ? 1 : 3;
    return ramp;
}

RGB ValueRamp::at(double x) const {
    if (!(x > stops_.front().position)) return stops_.front().value;  // NaN too
    if (x >= stops_.back().position) return stops_.back().value;
    const auto next = std::upper_bound(stops_.begin(), stops_.end(), x,
                                       [](double v, const Stop& s) { return v < s.position; });
    const Stop& b = *next;
    const Stop& a = *(next - 1);
    const double w = (x - a.position) / (b.position - a.position);
    return (1 - w) * a.value + w * b.value;
}

RGB ValueRamp::minimum() const {
    RGB m = stops_.front().value;
    for (const Stop& s : stops_) m = m.min(s.value);
    return m;
}

RGB ValueRamp::maximum() const {
    RGB m = stops_.front().value;
    for (const Stop& s : stops_) m = m.max(s.value);
    return m;
}

}  // namespace isotrace
