#include "geometry/variational/rbf_solver.h"

#include "geometry/instruction_set.h"
#include "geometry/variational/dense_solver_kernels.h"

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <tbb/parallel_for.h>

namespace isotrace::geometry {

namespace {

std::string describe(const Vec3& p) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", p.x(), p.y(), p.z());
    return text;
}

// Pairs closer than `tolerance` make two equal rows: the first such pair.
template <class Constraint>
void rejectCoincident(const std::vector<Constraint>& constraints, double tolerance, const char* kind) {
    // Hash grid of cell size `tolerance`: neighbours are in adjacent cells.
    std::map<std::array<long long, 3>, std::vector<size_t>> grid;
    auto cellOf = [&](const Vec3& p) {
        return std::array<long long, 3>{(long long)std::floor(p.x() / tolerance), (long long)std::floor(p.y() / tolerance),
                                        (long long)std::floor(p.z() / tolerance)};
    };
    for (size_t i = 0; i < constraints.size(); ++i) {
        const Vec3& p = constraints[i].position;
        const auto c = cellOf(p);
        for (int dx = -1; dx <= 1; ++dx)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dz = -1; dz <= 1; ++dz) {
                    auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == grid.end()) continue;
                    for (size_t j : it->second)
                        if ((constraints[j].position - p).norm() <= tolerance)
                            throw FitError(std::string(kind) + " constraints " + std::to_string(j) + " and " +
                                           std::to_string(i) + " coincide at " + describe(p) +
                                           ": two equal rows make the system singular; merge or remove one");
                }
        grid[c].push_back(i);
    }
}

double cube(double r) { return r * r * r; }

// True when f > 0 at a 24 x 24 grid on each face of the box.
bool positiveOnFaces(const VariationalField& f, const Box3& box) {
    constexpr int n = 24;
    for (int axis = 0; axis < 3; ++axis)
        for (int side = 0; side < 2; ++side)
            for (int i = 0; i <= n; ++i)
                for (int j = 0; j <= n; ++j) {
                    Vec3 p;
                    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
                    p[axis] = side ? box.upper[axis] : box.lower[axis];
                    p[u] = box.lower[u] + box.extent()[u] * i / n;
                    p[v] = box.lower[v] + box.extent()[v] * j / n;
                    if (!(f.value(p) > 0)) return false;
                }
    return true;
}

}  // namespace

double constraintValueScale(const ConstraintSet& set) {
    const double size = set.bounds().extent().norm();
    double scale = 0.0;
    for (const ValueConstraint& v : set.values) scale = std::max(scale, std::abs(v.value));
    for (const GradientConstraint& g : set.gradients) scale = std::max(scale, g.gradient.norm() * size);
    return scale;
}

double denseFitBytes(size_t unknowns) { return 8.0 * double(unknowns) * double(unknowns); }

void checkConstraints(const ConstraintSet& set) {
    const size_t n = set.values.size();
    if (n == 0) throw FitError("there are no value constraints: the surface's position is not fixed");
    for (const ValueConstraint& c : set.values)
        if (!c.position.allFinite() || !std::isfinite(c.value))
            throw FitError("a value constraint at " + describe(c.position) + " is not finite");
    for (const GradientConstraint& c : set.gradients)
        if (!c.position.allFinite() || !c.gradient.allFinite())
            throw FitError("a gradient constraint at " + describe(c.position) + " is not finite");
    bool anyNonZero = false;
    for (const ValueConstraint& c : set.values) anyNonZero |= c.value != 0.0;
    for (const GradientConstraint& c : set.gradients) anyNonZero |= c.gradient.squaredNorm() > 0.0;
    if (!anyNonZero)
        throw FitError("every constraint is zero, so f = 0 fits them all and there is no surface; add interior, "
                       "exterior or normal constraints");

    const double size = std::max(set.bounds().extent().norm(), 1e-300);
    rejectCoincident(set.values, 1e-9 * size, "value");
    rejectCoincident(set.gradients, 1e-9 * size, "gradient");
}

const DenseSolverKernels& denseSolverKernels() {
    static const DenseSolverKernels& chosen =
        tableForActiveSet(sse2::kDenseSolverKernels, avx2::kDenseSolverKernels, avx512::kDenseSolverKernels);
    return chosen;
}

VariationalField solveVariationalSystem(const ConstraintSet& set, double* reciprocalCondition) {
    const size_t n = set.values.size(), k = set.gradients.size();
    const size_t m = n + 3 * k;  // functionals: values, then gradient components
    const Box3 box = set.bounds();
    const double size = std::max(box.extent().norm(), 1e-300);
    // Positions relative to the box centre and in units of its size keep
    // the matrix entries near 1 whatever the model's scale.
    const Vec3 origin = box.center();
    const double scale = 1.0 / size;
    auto local = [&](const Vec3& p) { return Vec3((p - origin) * scale); };
    std::vector<Vec3> at(m);
    for (size_t i = 0; i < n; ++i) at[i] = local(set.values[i].position);
    for (size_t g = 0; g < k; ++g) at[n + 3 * g] = at[n + 3 * g + 1] = at[n + 3 * g + 2] = local(set.gradients[g].position);

    // Polynomial part: rows [1, x, y, z] for values, [0, e_a] for gradients.
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(m, 4);
    Eigen::VectorXd h(m);
    for (size_t i = 0; i < n; ++i) {
        P.row(i) << 1.0, at[i].x(), at[i].y(), at[i].z();
        h[i] = set.values[i].value;
    }
    for (size_t g = 0; g < k; ++g)
        for (int a = 0; a < 3; ++a) {
            P(n + 3 * g + a, 1 + a) = 1.0;
            // d/dx_local = size * d/dx.
            h[n + 3 * g + a] = set.gradients[g].gradient[a] * size;
        }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> rank(P);
    if (rank.rank() < 4)
        throw FitError("all " + std::to_string(n) +
                       " constraint points lie in one plane (or on a line) and no gradient constraint leaves it: a "
                       "degree-one polynomial is not determined; add a constraint off that plane");

    // A: phi between functionals (see variational_field.h for the signs).
    Eigen::MatrixXd A(m, m);
    tbb::parallel_for(size_t(0), m, [&](size_t col) {
        for (size_t row = col; row < m; ++row) {
            const Vec3 d = at[row] - at[col];
            const double r = d.norm();
            const bool rowValue = row < n, colValue = col < n;
            const int ra = rowValue ? 0 : int((row - n) % 3), ca = colValue ? 0 : int((col - n) % 3);
            double v;
            if (rowValue && colValue) v = cube(r);
            else if (!rowValue && colValue) v = 3.0 * r * d[ra];          // d_a phi(c_row - c_col)
            else if (rowValue && !colValue) v = -3.0 * r * d[ca];         // -d_a phi(c_row - c_col)
            else v = r > 0 ? -3.0 * ((ra == ca ? r : 0.0) + d[ra] * d[ca] / r) : 0.0;
            A(row, col) = v;
            A(col, row) = v;
        }
    });

    // Project onto the null space of P^T: with P = Q R, the last m - 4
    // columns of Q span it, and Q^T A Q's trailing block is positive definite.
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(P);
    const auto Q = qr.householderQ();
    A.applyOnTheLeft(Q.transpose());
    A.applyOnTheRight(Q);
    Eigen::VectorXd qh = Q.transpose() * h;
    const Eigen::Index free = Eigen::Index(m) - 4;
    Eigen::VectorXd gamma = Eigen::VectorXd::Zero(free);
    double rcond = 1.0;
    if (free > 0) {
        // The trailing block, factored in place (A is column-major, m rows).
        gamma = qh.tail(free);
        if (!denseSolverKernels().choleskySolve(&A(4, 4), size_t(free), size_t(A.outerStride()), gamma.data(), &rcond))
            throw FitError("the projected system is not positive definite: constraints too close together for "
                           "double precision (or nearly all in one plane); thin them out");
    }
    // Polynomial: R c = (Q^T h)_top - (Q^T A Q)_top,right gamma (that block
    // is untouched by the in-place factorisation).
    const Eigen::Vector4d top = qh.head<4>() - A.topRightCorner(4, free) * gamma;
    const Eigen::Vector4d c = qr.matrixQR().topLeftCorner<4, 4>().triangularView<Eigen::Upper>().solve(top);
    Eigen::VectorXd padded = Eigen::VectorXd::Zero(m);
    padded.tail(free) = gamma;
    const Eigen::VectorXd coefficients = Q * padded;

    // Back to world units: |x - c|^3 = |x_l - c_l|^3 / scale^3 and
    // grad phi scales by 1 / scale^2.
    VariationalField field;
    field.centers.reserve(n);
    field.weights.reserve(n);
    for (size_t i = 0; i < n; ++i) {
        field.centers.push_back(set.values[i].position);
        field.weights.push_back(coefficients[i] * cube(scale));
    }
    for (size_t g = 0; g < k; ++g) {
        field.gradientCenters.push_back(set.gradients[g].position);
        field.gradientWeights.push_back(
            Vec3(coefficients[n + 3 * g], coefficients[n + 3 * g + 1], coefficients[n + 3 * g + 2]) * (scale * scale));
    }
    // p0 + p . x_l with x_l = (x - origin) scale.
    field.linear = Vec3(c[1], c[2], c[3]) * scale;
    field.constant = c[0] - field.linear.dot(origin);
    if (reciprocalCondition) *reciprocalCondition = rcond;
    return field;
}

VariationalField fitVariationalField(const ConstraintSet& set, FitReport* report, const FitOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    const size_t n = set.values.size(), k = set.gradients.size();
    const size_t m = n + 3 * k;
    if (m + 4 > options.maxUnknowns) {
        char text[256];
        std::snprintf(text, sizeof text,
                      "%zu unknowns need %.1f GB for the dense solve, above the limit of %zu unknowns (%.1f GB); "
                      "use fewer constraints",
                      m + 4, denseFitBytes(m) / 1e9, options.maxUnknowns, denseFitBytes(options.maxUnknowns) / 1e9);
        throw FitError(text);
    }
    checkConstraints(set);
    double rcond = 1.0;
    VariationalField field = solveVariationalSystem(set, &rcond);
    const Box3 box = set.bounds();
    const double size = std::max(box.extent().norm(), 1e-300);
    // The domain must hold the whole surface: grow it until the field is
    // positive all over its faces (sampled), or warn.
    double margin = options.domainMargin;
    bool enclosed = false;
    for (int attempt = 0; attempt < 6 && !enclosed; ++attempt, margin *= 2) {
        field.domain = box.expanded(margin * size);
        enclosed = positiveOnFaces(field, field.domain);
    }

    FitReport r;
    r.unknowns = m + 4;
    r.reciprocalCondition = rcond;
    // Residuals against the world-unit field, as users will evaluate it.
    std::vector<double> residual(n + k, 0.0);
    tbb::parallel_for(size_t(0), n + k, [&](size_t i) {
        if (i < n) {
            residual[i] = std::abs(field.value(set.values[i].position) - set.values[i].value);
        } else {
            Vec3 g;
            field.valueAndGradient(set.gradients[i - n].position, g);
            residual[i] = (g - set.gradients[i - n].gradient).cwiseAbs().maxCoeff();
        }
    });
    for (double e : residual) r.maxResidual = std::max(r.maxResidual, e);
    // Residuals are judged against the size of what was asked for.
    const double valueScale = constraintValueScale(set);
    char text[160];
    if (r.maxResidual > 1e-6 * valueScale) {
        std::snprintf(text, sizeof text, "the fit misses its constraints by up to %.3g (constraint values up to %.3g)",
                      r.maxResidual, valueScale);
        r.warnings.push_back(text);
    }
    if (!enclosed)
        r.warnings.push_back("the surface reaches the edge of its domain even at a margin of " +
                             std::to_string(margin / 2) + " of the constraints' size; it is cut there");
    if (rcond < 1e-13) {
        std::snprintf(text, sizeof text, "the system is poorly conditioned (reciprocal condition %.3g); residual %.3g",
                      rcond, r.maxResidual);
        r.warnings.push_back(text);
    }
    // Without a constraint on the surface (or a gradient through it) and with
    // every value on one side, the field has no reason to cross zero.
    if (set.gradients.empty() && !set.values.empty()) {
        bool allOutside = true, allInside = true;
        for (const ValueConstraint& v : set.values) {
            allOutside = allOutside && v.value > 0;
            allInside = allInside && v.value < 0;
        }
        if (allOutside || allInside)
            r.warnings.push_back(std::string("every constraint is ") + (allOutside ? "exterior (positive)" : "interior (negative)") +
                                 " and none lies on the surface: the field likely has no surface; add boundary points");
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (report) *report = r;
    return field;
}

}  // namespace isotrace::geometry
