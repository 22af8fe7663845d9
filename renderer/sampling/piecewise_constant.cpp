#include "renderer/sampling/piecewise_constant.h"

#include <algorithm>
#include <cmath>

namespace isotrace {

PiecewiseConstant1D::PiecewiseConstant1D(std::vector<double> weights) : weights_(std::move(weights)) {
    const size_t n = weights_.size();
    cdf_.assign(n + 1, 0.0);
    for (size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + weights_[i] / double(n);
    integral_ = cdf_[n];
    if (!(integral_ > 0)) {
        for (size_t i = 0; i < n; ++i) cdf_[i + 1] = double(i + 1) / double(n);
    } else {
        for (double& c : cdf_) c /= integral_;
    }
    cdf_[n] = 1.0;
}

double PiecewiseConstant1D::sample(double u, double& pdf, size_t& bin) const {
    const size_t n = weights_.size();
    // The last bin whose cdf does not exceed u (bins of zero width are skipped).
    bin = std::min<size_t>(std::upper_bound(cdf_.begin(), cdf_.end(), u) - cdf_.begin(), n) - 1;
    while (bin + 1 < n && !(cdf_[bin + 1] > cdf_[bin])) ++bin;
    const double width = cdf_[bin + 1] - cdf_[bin];
    pdf = width * double(n);
    const double t = width > 0 ? (u - cdf_[bin]) / width : 0.5;
    return std::min((double(bin) + std::clamp(t, 0.0, 1.0)) / double(n), std::nextafter(1.0, 0.0));
}

double PiecewiseConstant1D::pdf(double x) const {
    const size_t n = weights_.size();
    const size_t bin = std::min<size_t>(size_t(std::max(0.0, x) * double(n)), n - 1);
    return (cdf_[bin + 1] - cdf_[bin]) * double(n);
}

PiecewiseConstant2D::PiecewiseConstant2D(const std::vector<double>& weights, int width, int height) {
    std::vector<double> rowIntegrals;
    for (int y = 0; y < height; ++y) {
        rows_.emplace_back(std::vector<double>(weights.begin() + size_t(y) * width, weights.begin() + size_t(y + 1) * width));
        rowIntegrals.push_back(rows_.back().integral());
    }
    marginal_ = PiecewiseConstant1D(std::move(rowIntegrals));
}

Eigen::Vector2d PiecewiseConstant2D::sample(const Eigen::Vector2d& u, double& pdf) const {
    double pdfV = 0.0, pdfU = 0.0;
    size_t row = 0, column = 0;
    const double v = marginal_.sample(u.y(), pdfV, row);
    const double x = rows_[row].sample(u.x(), pdfU, column);
    pdf = pdfV * pdfU;
    return {x, v};
}

double PiecewiseConstant2D::pdf(const Eigen::Vector2d& uv) const {
    const size_t row = std::min<size_t>(size_t(std::max(0.0, uv.y()) * double(rows_.size())), rows_.size() - 1);
    return marginal_.pdf(uv.y()) * rows_[row].pdf(uv.x());
}

}  // namespace isotrace
