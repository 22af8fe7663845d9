// Piecewise-constant densities for importance sampling tabulated functions
// (pbrt's PiecewiseConstant1D/2D): environment maps sample texels in
// proportion to their weight. Built once; sampling allocates nothing.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace isotrace {

/// A density on [0, 1) proportional to n non-negative values on equal bins.
class PiecewiseConstant1D {
public:
    PiecewiseConstant1D() = default;
    /// All-zero weights give the uniform density.
    explicit PiecewiseConstant1D(std::vector<double> weights);

    size_t size() const { return weights_.size(); }
    /// The sum of the weights over the bin count: the function's integral.
    double integral() const { return integral_; }
    double weight(size_t bin) const { return weights_[bin]; }
    /// A point x in [0, 1) with density pdf(x); `bin` receives its bin.
    double sample(double u, double& pdf, size_t& bin) const;
    double pdf(double x) const;

private:
    std::vector<double> weights_;
    std::vector<double> cdf_;  ///< size n + 1, from 0 to 1
    double integral_ = 0.0;
};

/// A density on [0, 1)^2 proportional to a width x height grid of weights
/// (row-major, rows along v): a marginal over rows, a conditional per row.
class PiecewiseConstant2D {
public:
    PiecewiseConstant2D() = default;
    PiecewiseConstant2D(const std::vector<double>& weights, int width, int height);

    /// A point (u, v) in [0, 1)^2 with density pdf(u, v).
    Eigen::Vector2d sample(const Eigen::Vector2d& u, double& pdf) const;
    double pdf(const Eigen::Vector2d& uv) const;

private:
    std::vector<PiecewiseConstant1D> rows_;
    PiecewiseConstant1D marginal_;
};

}  // namespace isotrace
