#pragma once
// Summary statistics of samples (percentiles, median, rounding for printing), for benchmarks.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace quiver::inline base {

/// Nearest-rank percentiles of a sample, sorted once however many are asked for.
class Percentiles {
 public:
  explicit Percentiles(std::vector<double> v) : v_(std::move(v)) {
    std::sort(v_.begin(), v_.end());
  }
  /// p in [0, 1]; 0 for an empty sample.
  double at(double p) const {
    if (v_.empty()) return 0;
    const auto i = static_cast<std::size_t>(p * static_cast<double>(v_.size() - 1) + 0.5);
    return v_[std::min(i, v_.size() - 1)];
  }

 private:
  std::vector<double> v_;
};

/// The median of `v` (nearest rank: the upper middle one when even).
inline double median(std::vector<double> v) { return Percentiles(std::move(v)).at(0.5); }

/// x rounded to `digits` decimals, for printing.
inline double round_to(double x, int digits) {
  const double scale = std::pow(10.0, digits);
  return std::round(x * scale) / scale;
}

}  // namespace quiver::base
