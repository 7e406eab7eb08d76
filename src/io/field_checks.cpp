#include "field_checks.h"

#include <fmt/format.h>

#include <cmath>

#include "core/error.h"

namespace nph::io {

void requireFinite(const std::string& path, const std::string& var, const std::vector<float>& data) {
  // Branch-free scan first (x - x is 0 for finite x, NaN for NaN and Inf), details only on failure.
  bool all_finite = true;
  for (float v : data) all_finite &= (v - v) == 0.0f;
  if (all_finite) return;
  for (std::size_t n = 0; n < data.size(); ++n) {
    if (!std::isfinite(data[n])) {
      throw InputError(fmt::format("{}: {} contains {} at element {}, expected finite values", path, var,
                                   std::isnan(data[n]) ? "NaN" : "Inf", n));
    }
  }
}

void requireRange(const std::string& path, const std::string& var, const std::vector<float>& data, double lo, double hi,
                  const std::string& what) {
  for (std::size_t n = 0; n < data.size(); ++n) {
    const double v = data[n];
    if (!(v >= lo && v <= hi)) {
      throw InputError(
          fmt::format("{}: {} is {} at element {}, expected {} in [{}, {}]", path, var, v, n, what, lo, hi));
    }
  }
}

void requireAtMost(const std::string& path, const std::string& var, const std::vector<float>& data, double hi,
                   const std::string& what) {
  const auto h = static_cast<float>(hi);
  bool all_ok = true;
  for (float v : data) all_ok &= v <= h;  // branch-free scan, details only on failure
  if (all_ok) return;
  for (std::size_t n = 0; n < data.size(); ++n) {
    if (!(data[n] <= h)) {
      throw InputError(
          fmt::format("{}: {} is {} at element {}, expected {} of at most {}", path, var, data[n], n, what, hi));
    }
  }
}

std::int64_t clampNegative(std::vector<float>& data) {
  std::int64_t count = 0;
  for (float& v : data) {  // branch-free so that it vectorises
    const bool negative = v < 0.0f;
    count += negative;
    v = negative ? 0.0f : v;
  }
  return count;
}

void requireWithinBudget(const std::string& path, const std::string& what, double points, int fields,
                         std::size_t budget_bytes) {
  const double bytes = points * fields * double(sizeof(float));
  if (bytes > double(budget_bytes)) {
    throw InputError(
        fmt::format("{}: {} declares {:.0f} points x {} fields = {:.2f} GiB, more than the memory budget of {:.2f} GiB "
                    "(LoadOptions::memory_budget_bytes or NEPHELE_IO_MEMORY_BUDGET_MB)",
                    path, what, points, fields, bytes / double(1 << 30), double(budget_bytes) / double(1 << 30)));
  }
}

}  // namespace nph::io
