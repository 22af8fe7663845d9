#include "geometry/variational/constraints.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "geometry/input_error.h"
#include "geometry/mesh_file.h"

namespace isotrace::geometry {

Box3 ConstraintSet::bounds() const {
    Box3 box;
    for (const ValueConstraint& c : values) box.extend(c.position);
    for (const GradientConstraint& c : gradients) box.extend(c.position);
    return box;
}

std::vector<OrientedPoint> readOrientedPoints(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw InputError(path, "", "cannot open the oriented point set");
    std::vector<OrientedPoint> points;
    std::string line;
    for (size_t number = 1; std::getline(in, line); ++number) {
        const size_t hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        std::istringstream fields(line);
        double v[6];
        int n = 0;
        while (n < 6 && fields >> v[n]) ++n;
        std::string rest;
        const std::string where = "line " + std::to_string(number);
        if (n < 6 || (fields >> rest))
            throw InputError(path, where, "expected six numbers \"x y z nx ny nz\"");
        for (double x : v)
            if (!std::isfinite(x)) throw InputError(path, where, "a value is not a finite number");
        const Vec3 normal(v[3], v[4], v[5]);
        if (!(normal.norm() > 0)) throw InputError(path, where, "the normal is zero");
        points.push_back({Vec3(v[0], v[1], v[2]), normal.normalized()});
    }
    if (points.empty()) throw InputError(path, "", "the oriented point set is empty");
    return points;
}

std::vector<OrientedPoint> orientedPointsOfMesh(const IndexedMesh& mesh) {
    const std::vector<Vec3> normals = areaWeightedVertexNormals(mesh);
    std::vector<bool> used(mesh.vertices.size(), false);
    for (const auto& t : mesh.triangles)
        for (uint32_t v : t) used[v] = true;
    std::vector<OrientedPoint> points;
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
        if (used[v]) points.push_back({mesh.vertices[v], normals[v]});  // stray vertices carry no surface
    return points;
}

double defaultNormalOffset(const std::vector<OrientedPoint>& points) {
    Box3 box;
    for (const OrientedPoint& p : points) box.extend(p.position);
    return points.empty() ? 0.0 : 0.01 * box.extent().norm();
}

ConstraintSet constraintsFromOrientedPoints(const std::vector<OrientedPoint>& points, double normalOffset, bool hermite) {
    ConstraintSet set;
    for (const OrientedPoint& p : points) {
        if (hermite)
            set.addHermite(p.position, p.normal);
        else
            set.addNormal(p.position, p.normal, normalOffset);
    }
    return set;
}

}  // namespace isotrace::geometry
