#include "renderer/point_export.h"

#include <cstring>
#include <sstream>
#include <stdexcept>

#include "geometry/atomic_file.h"
#include "geometry/mesh_file.h"

namespace isotrace {

namespace {

void appendFloat(std::string& bytes, double value) {
    const float f = float(value);
    char raw[4];
    std::memcpy(raw, &f, 4);  // little-endian hosts only (x86-64, arm64), as the header says
    bytes.append(raw, 4);
}

}  // namespace

bool isPointSetExtension(const std::string& path) {
    const std::string e = geometry::lowercaseExtension(path);
    return e == ".ply" || e == ".xyz";
}

void writePoints(const std::string& path, const std::vector<geometry::SurfaceParticle>& points) {
    const std::string e = geometry::lowercaseExtension(path);
    std::string bytes;
    if (e == ".ply") {
        bytes = "ply\nformat binary_little_endian 1.0\ncomment isotrace particles\nelement vertex " +
                std::to_string(points.size()) +
                "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                "property float nz\nproperty float radius\nend_header\n";
        bytes.reserve(bytes.size() + 28 * points.size());
        for (const auto& p : points) {
            for (int k = 0; k < 3; ++k) appendFloat(bytes, p.position[k]);
            for (int k = 0; k < 3; ++k) appendFloat(bytes, p.normal[k]);
            appendFloat(bytes, p.radius);
        }
    } else if (e == ".xyz") {
        std::ostringstream out;
        out.precision(9);
        for (const auto& p : points)
            out << p.position.x() << ' ' << p.position.y() << ' ' << p.position.z() << ' ' << p.normal.x() << ' '
                << p.normal.y() << ' ' << p.normal.z() << '\n';
        bytes = out.str();
    } else {
        throw std::runtime_error(path + ": unknown point set format (use .ply or .xyz)");
    }
    geometry::writeFileAtomically(path, bytes);
}

}  // namespace isotrace
