#pragma once
// Summary statistics shared by the benchmarks: nearest-rank percentiles, the median, rounding for
// printing.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

namespace quiver::tools::bench {

/// Nearest-rank percentiles of a sample, sorted once however many are asked for.
class Percentiles {
 public:
  explicit Percentiles(std::vector<double> v) : v_(std::move(v)) {
    std::sort(v_.begin(), v_.end());
  }
  /// @pre p in [0, 1]. @returns the sample's p-quantile (nearest rank); 0 for an empty sample.
  double at(double p) const {
    if (v_.empty()) return 0;
    const auto i = static_cast<std::size_t>(p * static_cast<double>(v_.size() - 1) + 0.5);
    return v_[std::min(i, v_.size() - 1)];
  }

 private:
  std::vector<double> v_;
};

/// @returns the median of `v` (nearest rank: the upper middle one when even); 0 when empty.
inline double median(std::vector<double> v) { return Percentiles(std::move(v)).at(0.5); }

/// @returns x rounded to `digits` decimals, for printing.
inline double round_to(double x, int digits) {
  const double scale = std::pow(10.0, digits);
  return std::round(x * scale) / scale;
}

}  // namespace quiver::tools::bench
