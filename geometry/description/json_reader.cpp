#include "geometry/description/json_reader.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace isotrace::geometry {

namespace {

std::string typeName(const Json& j) {
    switch (j.type()) {
        case Json::value_t::null: return "null";
        case Json::value_t::boolean: return "a boolean";
        case Json::value_t::string: return "a string";
        case Json::value_t::array: return "an array";
        case Json::value_t::object: return "an object";
        case Json::value_t::discarded: return "nothing";
        default: return "a number";
    }
}

size_t editDistance(const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t up = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
            diagonal = up;
        }
    }
    return row[b.size()];
}


}  // namespace

std::string joinNames(std::vector<std::string> names) {
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : ", ") + ("\"" + n + "\"");
    return s;
}

namespace {
std::string lineAndColumn(const std::string& text, size_t offset) {
    size_t line = 1, column = 1;
    for (size_t i = 0; i < std::min(offset, text.size()); ++i) {
        if (text[i] == '\n') {
            ++line;
            column = 1;
        } else {
            ++column;
        }
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}
}  // namespace

namespace {

// nlohmann's parser and destructor recurse once per nesting level, so text
// nested deeper than this is refused before parsing (a CSG tree 100,000
// levels deep would otherwise end the stack). Field graphs stop at 1,000
// levels of operands anyway, two JSON levels each.
constexpr int kMaxJsonDepth = 4000;

void checkNesting(const std::string& text, const std::string& sourceName) {
    int depth = 0;
    bool inString = false, escaped = false;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (inString) {
            if (escaped) escaped = false;
            else if (c == '\\') escaped = true;
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') inString = true;
        else if (c == '[' || c == '{') {
            if (++depth > kMaxJsonDepth)
                throw InputError(sourceName, lineAndColumn(text, i),
                                 "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
        } else if (c == ']' || c == '}') {
            --depth;
        }
    }
}

}  // namespace

Json parseJsonText(const std::string& text, const std::string& sourceName) {
    checkNesting(text, sourceName);
    try {
        return Json::parse(text);
    } catch (const Json::parse_error& e) {
        // nlohmann reports a byte offset; users want line and column.
        std::string what = e.what();
        const size_t pos = what.find("syntax error");
        if (pos != std::string::npos) what = what.substr(pos);
        throw InputError(sourceName, lineAndColumn(text, e.byte == 0 ? 0 : e.byte - 1), "malformed JSON: " + what);
    } catch (const Json::out_of_range& e) {
        // A number too large for a double: nlohmann names the token, not its place.
        std::string what = e.what();
        const size_t open = what.find('\''), close = what.rfind('\'');
        std::string where;
        if (open != std::string::npos && close > open) {
            const size_t at = text.find(what.substr(open + 1, close - open - 1));
            if (at != std::string::npos) where = lineAndColumn(text, at);
        }
        const size_t pos = what.find("number overflow");
        throw InputError(sourceName, where, pos != std::string::npos ? what.substr(pos) : what);
    }
}

Json parseJsonFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot open file for reading");
    std::stringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) throw InputError(path, "", "cannot read file");
    return parseJsonText(buffer.str(), path);
}

std::string jsonPointerAppend(const std::string& pointer, const std::string& key) {
    std::string escaped;
    for (char c : key) {
        if (c == '~') escaped += "~0";
        else if (c == '/') escaped += "~1";
        else escaped += c;
    }
    return pointer + "/" + escaped;
}
std::string jsonPointerAppend(const std::string& pointer, size_t index) {
    return pointer + "/" + std::to_string(index);
}

std::optional<std::string> nearestName(const std::string& name, const std::vector<std::string>& candidates) {
    std::optional<std::string> best;
    size_t bestDistance = std::max<size_t>(2, name.size() / 3) + 1;
    for (const std::string& c : candidates) {
        const size_t d = editDistance(name, c);
        if (d < bestDistance) {
            bestDistance = d;
            best = c;
        }
    }
    return best;
}

JsonObjectReader::JsonObjectReader(const Json& json, std::string pointer, std::string file)
    : json_(&json), pointer_(std::move(pointer)), file_(std::move(file)) {
    if (!json.is_object())
        throw InputError(file_, pointer_.empty() ? "/" : pointer_, "expected an object, found " + typeName(json));
}

bool JsonObjectReader::has(const std::string& key) {
    asked_.push_back(key);
    return json_->contains(key);
}

const Json* JsonObjectReader::optionalValue(const std::string& key) {
    asked_.push_back(key);
    const auto it = json_->find(key);
    return it == json_->end() ? nullptr : &*it;
}

const Json& JsonObjectReader::value(const std::string& key) {
    const Json* v = optionalValue(key);
    if (!v) fail(key, "missing required key \"" + key + "\"");
    return *v;
}

void JsonObjectReader::fail(const std::string& key, const std::string& message) const {
    throw InputError(file_, pointerOf(key), message);
}
void JsonObjectReader::failHere(const std::string& message) const {
    throw InputError(file_, pointer_.empty() ? "/" : pointer_, message);
}

double JsonObjectReader::asNumber(const Json& j, const std::string& pointer, const std::string& file) {
    if (!j.is_number()) throw InputError(file, pointer, "expected a number, found " + typeName(j));
    const double v = j.get<double>();
    if (!std::isfinite(v)) throw InputError(file, pointer, "number is not finite");
    return v;
}

Vec3 JsonObjectReader::asVec3(const Json& j, const std::string& pointer, const std::string& file) {
    if (!j.is_array() || j.size() != 3)
        throw InputError(file, pointer, "expected an array of 3 numbers, found " + typeName(j) +
                                            (j.is_array() ? " of " + std::to_string(j.size()) : ""));
    return {asNumber(j[0], pointer + "/0", file), asNumber(j[1], pointer + "/1", file),
            asNumber(j[2], pointer + "/2", file)};
}

double JsonObjectReader::number(const std::string& key) { return asNumber(value(key), pointerOf(key), file_); }
double JsonObjectReader::number(const std::string& key, double fallback) {
    const Json* v = optionalValue(key);
    return v ? asNumber(*v, pointerOf(key), file_) : fallback;
}
double JsonObjectReader::positiveNumber(const std::string& key) {
    const double v = number(key);
    if (!(v > 0)) fail(key, "must be greater than 0, found " + std::to_string(v));
    return v;
}
double JsonObjectReader::positiveNumber(const std::string& key, double fallback) {
    if (!has(key)) return fallback;
    return positiveNumber(key);
}

long long JsonObjectReader::integer(const std::string& key, long long fallback, long long minimum, long long maximum) {
    const Json* v = optionalValue(key);
    if (!v) return fallback;
    if (!v->is_number_integer() && !(v->is_number_float() && std::floor(v->get<double>()) == v->get<double>()))
        fail(key, "expected a whole number, found " + typeName(*v) + (v->is_number() ? " " + v->dump() : ""));
    const double d = v->get<double>();
    if (d < static_cast<double>(minimum) || d > static_cast<double>(maximum))
        fail(key, "must be between " + std::to_string(minimum) + " and " + std::to_string(maximum) + ", found " +
                      v->dump());
    return v->get<long long>();
}

bool JsonObjectReader::boolean(const std::string& key, bool fallback) {
    const Json* v = optionalValue(key);
    if (!v) return fallback;
    if (!v->is_boolean()) fail(key, "expected true or false, found " + typeName(*v));
    return v->get<bool>();
}

std::string JsonObjectReader::string(const std::string& key) {
    const Json& v = value(key);
    if (!v.is_string()) fail(key, "expected a string, found " + typeName(v));
    return v.get<std::string>();
}
std::string JsonObjectReader::string(const std::string& key, const std::string& fallback) {
    if (!has(key)) return fallback;
    return string(key);
}

std::string JsonObjectReader::choice(const std::string& key, const std::vector<std::string>& names,
                                     const std::string& fallback) {
    const std::string s = fallback.empty() ? string(key) : string(key, fallback);
    if (std::find(names.begin(), names.end(), s) != names.end()) return s;
    std::string message = "unknown value \"" + s + "\"";
    if (auto near = nearestName(s, names)) message += " (did you mean \"" + *near + "\"?)";
    fail(key, message + "; valid values: " + joinNames(names));
}

Vec3 JsonObjectReader::vec3(const std::string& key) { return asVec3(value(key), pointerOf(key), file_); }
Vec3 JsonObjectReader::vec3(const std::string& key, const Vec3& fallback) {
    const Json* v = optionalValue(key);
    return v ? asVec3(*v, pointerOf(key), file_) : fallback;
}

std::vector<double> JsonObjectReader::numbers(const std::string& key) {
    const Json& v = value(key);
    if (!v.is_array()) fail(key, "expected an array of numbers, found " + typeName(v));
    std::vector<double> out;
    for (size_t i = 0; i < v.size(); ++i) out.push_back(asNumber(v[i], jsonPointerAppend(pointerOf(key), i), file_));
    return out;
}

JsonObjectReader JsonObjectReader::object(const std::string& key) {
    return JsonObjectReader(value(key), pointerOf(key), file_);
}

void JsonObjectReader::finish() const {
    for (auto it = json_->begin(); it != json_->end(); ++it) {
        if (std::find(asked_.begin(), asked_.end(), it.key()) != asked_.end()) continue;
        std::string message = "unknown key \"" + it.key() + "\"";
        if (auto near = nearestName(it.key(), asked_)) message += " (did you mean \"" + *near + "\"?)";
        else message += "; valid keys here: " + joinNames(asked_);
        throw InputError(file_, pointerOf(it.key()), message);
    }
}

}  // namespace isotrace::geometry
