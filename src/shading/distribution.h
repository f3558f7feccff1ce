// Piecewise-constant distributions on [0, 1) and [0, 1)², for importance sampling tabulated
// functions (the lat-long environment). pdf() is the density with respect to the unit
// interval / square; sampling is by inverting the cumulative sum. A function that is zero
// everywhere samples uniformly (so a pdf always exists). Immutable after construction.
#pragma once
#include <algorithm>
#include <vector>

namespace rayes {

class Distribution1D {
 public:
  Distribution1D() = default;
  explicit Distribution1D(std::vector<float> f) : f_(std::move(f)), cdf_(f_.size() + 1, 0.0) {
    const size_t n = f_.size();
    for (size_t i = 0; i < n; ++i) cdf_[i + 1] = cdf_[i] + std::max(0.0f, f_[i]) / double(n);
    integral_ = mean_ = cdf_[n];
    if (!(integral_ > 0)) {
      for (size_t i = 0; i < n; ++i) { f_[i] = 1; cdf_[i + 1] = double(i + 1) / n; }
      integral_ = 1;
    } else {
      for (size_t i = 1; i <= n; ++i) cdf_[i] /= integral_;
    }
  }
  size_t size() const { return f_.size(); }
  double integral() const { return mean_; }  // mean of the function (0 for a zero function)
  float pdf(size_t i) const { return float(std::max(0.0f, f_[i]) / integral_); }
  // x in [0, 1), its density, and the cell index.
  float sample(float u, float& pdf, size_t& index) const {
    const size_t n = f_.size();
    const auto it = std::upper_bound(cdf_.begin(), cdf_.end(), double(u));
    index = std::min<size_t>(n - 1, size_t(std::max<ptrdiff_t>(0, it - cdf_.begin() - 1)));
    const double width = cdf_[index + 1] - cdf_[index];
    double du = width > 0 ? (u - cdf_[index]) / width : 0.5;
    du = std::clamp(du, 0.0, 1.0);
    pdf = this->pdf(index);
    const float x = float((index + du) / n);
    return std::min(x, 0.99999994f);
  }

 private:
  std::vector<float> f_;
  std::vector<double> cdf_;
  double integral_ = 0, mean_ = 0;
};

// f(x, y) given as rows (y) of columns (x): rows[j][i].
class Distribution2D {
 public:
  Distribution2D() = default;
  Distribution2D(const std::vector<float>& f, size_t width, size_t height) {
    std::vector<float> marginal(height);
    for (size_t j = 0; j < height; ++j) {
      rows_.emplace_back(std::vector<float>(f.begin() + j * width, f.begin() + (j + 1) * width));
      marginal[j] = float(rows_.back().integral());
    }
    marginal_ = Distribution1D(std::move(marginal));
  }
  bool empty() const { return rows_.empty(); }
  // (x, y) in [0, 1)² and its density.
  void sample(float u1, float u2, float& x, float& y, float& pdf) const {
    float py = 0, px = 0;
    size_t j = 0, i = 0;
    y = marginal_.sample(u2, py, j);
    x = rows_[j].sample(u1, px, i);
    pdf = px * py;
  }
  float pdf(float x, float y) const {
    const size_t h = rows_.size(), w = rows_[0].size();
    const size_t j = std::min(h - 1, size_t(std::max(0.0f, y) * h));
    const size_t i = std::min(w - 1, size_t(std::max(0.0f, x) * w));
    return marginal_.pdf(j) * rows_[j].pdf(i);
  }

 private:
  std::vector<Distribution1D> rows_;
  Distribution1D marginal_;
};

}  // namespace rayes
