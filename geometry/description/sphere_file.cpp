#include "geometry/description/sphere_file.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "geometry/errors.h"

namespace isotrace::geometry {

namespace {

// A scalar property's size in bytes, or 0 for an unknown type name.
size_t scalarSize(const std::string& type) {
    static const std::map<std::string, size_t> sizes = {
        {"char", 1},  {"uchar", 1},  {"int8", 1},   {"uint8", 1},  {"short", 2},   {"ushort", 2},  {"int16", 2},
        {"uint16", 2}, {"int", 4},   {"uint", 4},   {"int32", 4},  {"uint32", 4},  {"float", 4},   {"float32", 4},
        {"double", 8}, {"float64", 8}};
    const auto it = sizes.find(type);
    return it == sizes.end() ? 0 : it->second;
}

// A little-endian scalar of the given type at `bytes`, as a double.
double decodeScalar(const std::string& type, const unsigned char* bytes) {
    auto as = [bytes](auto value) {
        std::memcpy(&value, bytes, sizeof(value));
        return double(value);
    };
    if (type == "char" || type == "int8") return as(int8_t());
    if (type == "uchar" || type == "uint8") return as(uint8_t());
    if (type == "short" || type == "int16") return as(int16_t());
    if (type == "ushort" || type == "uint16") return as(uint16_t());
    if (type == "int" || type == "int32") return as(int32_t());
    if (type == "uint" || type == "uint32") return as(uint32_t());
    if (type == "float" || type == "float32") return as(float());
    return as(double());
}

struct Property {
    std::string name, type;
    size_t offset = 0;  ///< in a binary row
};

}  // namespace

std::vector<SphereField> readSphereFile(const std::string& path, std::optional<double> defaultRadius,
                                        double maxSpheres) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, "", "sphere file not found");
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path, "", "cannot open the sphere file");

    // The header: "ply", the format, the first element (vertex) and its
    // properties, then anything up to "end_header".
    std::string line;
    long number = 0;
    auto fail = [&](const std::string& message) -> void { throw InputError(path, "line " + std::to_string(number), message); };
    if (!std::getline(in, line) || (++number, line != "ply" && line != "ply\r"))
        fail("not a PLY file (its first line must be \"ply\")");
    bool binary = false, sawFormat = false, inVertex = false, sawVertex = false, ended = false;
    long long count = 0;
    std::vector<Property> properties;
    size_t rowBytes = 0;
    while (!ended && std::getline(in, line)) {
        ++number;
        if (number > 1000) fail("no \"end_header\" within 1,000 lines");
        std::istringstream words(line);
        std::string word;
        if (!(words >> word) || word == "comment" || word == "obj_info") continue;
        if (word == "format") {
            std::string format;
            words >> format;
            if (format == "binary_little_endian") binary = true;
            else if (format != "ascii") fail("format \"" + format + "\" is not read: use ascii or binary_little_endian");
            sawFormat = true;
        } else if (word == "element") {
            std::string name;
            words >> name;
            if (!sawVertex && name != "vertex") fail("the first element must be \"vertex\", not \"" + name + "\"");
            inVertex = !sawVertex;
            if (inVertex && !(words >> count)) fail("the vertex element needs a count");
            sawVertex = true;
        } else if (word == "property") {
            if (!inVertex) continue;
            std::string type, name;
            words >> type >> name;
            if (type == "list") fail("list properties in the vertex element are not read");
            const size_t size = scalarSize(type);
            if (size == 0) fail("unknown property type \"" + type + "\"");
            properties.push_back({name, type, rowBytes});
            rowBytes += size;
        } else if (word == "end_header") {
            ended = true;
        } else {
            fail("unexpected \"" + word + "\" in the header");
        }
    }
    if (!ended) fail("no \"end_header\" line: not a complete PLY header");
    if (!sawFormat) fail("the header has no format line");
    if (!sawVertex) fail("the header has no vertex element");

    auto column = [&](const std::string& name) -> int {
        for (size_t i = 0; i < properties.size(); ++i)
            if (properties[i].name == name) return int(i);
        return -1;
    };
    const std::array<int, 3> xyz = {column("x"), column("y"), column("z")};
    const int radiusColumn = column("radius");
    if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0)
        throw InputError(path, "header", "the vertex element needs properties x, y and z (and radius, or a radius in the scene)");
    if (radiusColumn < 0 && !defaultRadius)
        throw InputError(path, "header", "no radius property: give each vertex a radius, or the scatter's shape a radius");
    if (count <= 0) throw InputError(path, "header", "the file holds no spheres");
    if (double(count) > maxSpheres)
        throw InputError(path, "header", std::to_string(count) + " spheres would need more than half of this machine's memory");
    const uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (binary && double(count) * double(rowBytes) > double(bytes))
        throw InputError(path, "header", "the header claims " + std::to_string(count) + " vertices, more than the file's " +
                                             std::to_string(bytes) + " bytes hold");

    std::vector<SphereField> spheres;
    spheres.reserve(size_t(count));
    std::vector<double> row(properties.size());
    std::vector<unsigned char> raw(rowBytes);
    for (long long v = 0; v < count; ++v) {
        const std::string where = "vertex " + std::to_string(v);
        if (binary) {
            if (!in.read(reinterpret_cast<char*>(raw.data()), std::streamsize(rowBytes)))
                throw InputError(path, where, "the file ends before vertex " + std::to_string(v) + " of " + std::to_string(count));
            for (size_t i = 0; i < properties.size(); ++i) row[i] = decodeScalar(properties[i].type, raw.data() + properties[i].offset);
        } else {
            ++number;
            if (!std::getline(in, line))
                throw InputError(path, where, "the file ends before vertex " + std::to_string(v) + " of " + std::to_string(count));
            std::istringstream values(line);
            for (size_t i = 0; i < properties.size(); ++i) {
                std::string token;
                char* end = nullptr;
                if (!(values >> token) || (row[i] = std::strtod(token.c_str(), &end), *end != '\0'))
                    throw InputError(path, "line " + std::to_string(number),
                                     "expected " + std::to_string(properties.size()) + " numbers (" + where + ")");
            }
        }
        SphereField s{Vec3(row[size_t(xyz[0])], row[size_t(xyz[1])], row[size_t(xyz[2])]),
                      radiusColumn >= 0 ? row[size_t(radiusColumn)] : *defaultRadius};
        if (!s.center.allFinite()) throw InputError(path, where, "a coordinate is not a finite number");
        if (!(s.radius > 0) || !std::isfinite(s.radius))
            throw InputError(path, where, "the radius must be a finite number greater than 0");
        spheres.push_back(s);
    }
    return spheres;
}

}  // namespace isotrace::geometry
