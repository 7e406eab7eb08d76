#include "field_checks.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>

#include "core/error.h"

namespace nph::io {

namespace {

/// Whether every value lies in [lo, hi] (NaN never does): a branch-free scan with an integer
/// accumulator, so that it vectorises (a `bool &=` accumulator does not; issue 19, convert speed).
/// The details are looked up only on failure.
bool allWithin(const std::vector<float>& data, float lo, float hi) {
  std::uint32_t outside = 0;
  for (const float v : data) outside |= static_cast<std::uint32_t>(!(v >= lo)) | static_cast<std::uint32_t>(!(v <= hi));
  return outside == 0;
}

/// The smallest float >= x and the largest float <= x: for a float v, v >= x exactly when
/// v >= floatAtLeast(x), and v <= x exactly when v <= floatAtMost(x), so a range given in double
/// is checked in float without moving its ends.
float floatAtLeast(double x) {
  const auto f = static_cast<float>(x);
  return double(f) < x ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}
float floatAtMost(double x) {
  const auto f = static_cast<float>(x);
  return double(f) > x ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}

}  // namespace

void requireFinite(const std::string& path, const std::string& var, const std::vector<float>& data) {
  // The lowest and highest finite floats: NaN and ±Inf lie outside.
  if (allWithin(data, std::numeric_limits<float>::lowest(), std::numeric_limits<float>::max())) return;
  for (std::size_t n = 0; n < data.size(); ++n) {
    if (!std::isfinite(data[n])) {
      throw InputError(fmt::format("{}: {} contains {} at element {}, expected finite values", path, var,
                                   std::isnan(data[n]) ? "NaN" : "Inf", n));
    }
  }
}

void requireRange(const std::string& path, const std::string& var, const std::vector<float>& data, double lo, double hi,
                  const std::string& what) {
  if (allWithin(data, floatAtLeast(lo), floatAtMost(hi))) return;
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
  const auto h = static_cast<float>(hi);  // compared in float: 0.1f passes "at most 0.1"
  if (allWithin(data, -std::numeric_limits<float>::infinity(), h)) return;
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
