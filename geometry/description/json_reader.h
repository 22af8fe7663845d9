// Typed, path-aware access to JSON descriptions, shared by the field parser
// and the renderer's scene loader. Every getter records the key it was asked
// for; finish() rejects keys never asked for, suggesting the nearest valid
// one, so a typo fails at its JSON path instead of becoming a silent default.
#pragma once

#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "geometry/errors.h"
#include "geometry/vector_types.h"

namespace isotrace::geometry {

using Json = nlohmann::json;

/// Reads and parses a JSON file; syntax errors name line and column.
Json parseJsonFile(const std::string& path);
/// Parses JSON text; `sourceName` is used in error messages.
Json parseJsonText(const std::string& text, const std::string& sourceName);

/// Appends a key or index to a JSON pointer, escaping '~' and '/'.
std::string jsonPointerAppend(const std::string& pointer, const std::string& key);
std::string jsonPointerAppend(const std::string& pointer, size_t index);

/// The names quoted, sorted, without repeats, separated by commas.
std::string joinNames(std::vector<std::string> names);

/// Name among `candidates` closest to `name` by edit distance, if close enough.
std::optional<std::string> nearestName(const std::string& name, const std::vector<std::string>& candidates);

class JsonObjectReader {
public:
    /// `json` must outlive the reader. Fails unless `json` is an object.
    JsonObjectReader(const Json& json, std::string pointer, std::string file);

    const std::string& pointer() const { return pointer_; }
    const Json& json() const { return *json_; }
    const std::string& file() const { return file_; }
    std::string pointerOf(const std::string& key) const { return jsonPointerAppend(pointer_, key); }

    bool has(const std::string& key);
    /// The raw value of a present key (marks it used), or fails naming it.
    const Json& value(const std::string& key);
    const Json* optionalValue(const std::string& key);

    double number(const std::string& key);
    double number(const std::string& key, double fallback);
    /// A number that must be > 0.
    double positiveNumber(const std::string& key);
    double positiveNumber(const std::string& key, double fallback);
    long long integer(const std::string& key, long long fallback, long long minimum, long long maximum);
    bool boolean(const std::string& key, bool fallback);
    std::string string(const std::string& key);
    std::string string(const std::string& key, const std::string& fallback);
    /// A string from a fixed set; an unknown one fails listing the valid names.
    std::string choice(const std::string& key, const std::vector<std::string>& names, const std::string& fallback);
    Vec3 vec3(const std::string& key);
    Vec3 vec3(const std::string& key, const Vec3& fallback);
    std::vector<double> numbers(const std::string& key);
    JsonObjectReader object(const std::string& key);

    /// Fails on any key that no getter asked for.
    void finish() const;
    [[noreturn]] void fail(const std::string& key, const std::string& message) const;
    [[noreturn]] void failHere(const std::string& message) const;

    // Helpers for values found inside arrays and nested structures.
    static double asNumber(const Json& j, const std::string& pointer, const std::string& file);
    static Vec3 asVec3(const Json& j, const std::string& pointer, const std::string& file);

private:
    const Json* json_;
    std::string pointer_;
    std::string file_;
    std::vector<std::string> asked_;
};

}  // namespace isotrace::geometry
