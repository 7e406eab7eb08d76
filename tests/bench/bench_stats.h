#pragma once
// Statistics the benchmarks report (docs/benchmarks.md: medians and ratios, never one time).
#include <algorithm>
#include <vector>

namespace nph::bench {

/// The median of `v` (the mean of the two middle values for an even count; 0 when empty).
inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n == 0 ? 0.0 : (n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]));
}

}  // namespace nph::bench
