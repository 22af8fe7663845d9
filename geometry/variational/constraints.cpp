#include "geometry/variational/constraints.h"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <fstream>
#include <sstream>

#include "geometry/errors.h"
#include "geometry/mesh_file.h"

namespace isotrace::geometry {

Box3 ConstraintSet::bounds() const {
    Box3 box;
    for (const ValueConstraint& c : values) box.extend(c.position);
    for (const GradientConstraint& c : gradients) box.extend(c.position);
    return box;
}

bool isOrientedPointFile(const std::string& path) {
    const std::string extension = lowercaseExtension(path);
    return extension == ".xyz" || extension == ".pwn" || extension == ".pts";
}

std::vector<OrientedPoint> readOrientedPoints(const std::string& path) {
    if (!isOrientedPointFile(path))
        throw InputError(path, "", "unknown point-set format \"" + lowercaseExtension(path) +
                                       "\"; oriented points are read from .xyz, .pwn or .pts text (x y z nx ny nz per line)");
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
    checkPointsOutlineASolid(points, path);
    if (points.size() < kMinimumOrientedPoints)
        throw InputError(path, "", "only " + std::to_string(points.size()) + " points; a surface needs at least " +
                                       std::to_string(kMinimumOrientedPoints));
    return points;
}

void checkPointsOutlineASolid(const std::vector<OrientedPoint>& points, const std::string& file) {
    // The spread of the points about their mean: no spread along some axis
    // means a plane, a line or a single place.
    Vec3 mean = Vec3::Zero();
    for (const OrientedPoint& p : points) mean += p.position;
    mean /= double(points.size());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (const OrientedPoint& p : points) covariance += (p.position - mean) * (p.position - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spread(covariance / double(points.size()));
    const Eigen::Vector3d deviation = spread.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
    if (!(deviation[0] > 1e-6 * deviation[2]))
        throw InputError(file, "", "all " + std::to_string(points.size()) +
                                       " points lie in one plane (or on a line, or at one place): they cannot outline a solid");
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
