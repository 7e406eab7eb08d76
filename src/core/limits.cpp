#include "core/limits.h"

#include <fmt/format.h>

#include "core/env.h"
#include "core/error.h"

namespace nph::limits {

std::optional<std::uint64_t> checkedProduct(std::initializer_list<std::uint64_t> factors) {
  std::uint64_t product = 1;
  for (const std::uint64_t f : factors) {
    if (__builtin_mul_overflow(product, f, &product)) return std::nullopt;
  }
  return product;
}

std::uint64_t requireProductWithin(const std::string& file, const std::string& field,
                                   std::initializer_list<std::uint64_t> factors, std::uint64_t limit,
                                   const std::string& how_to_raise) {
  const auto product = checkedProduct(factors);
  if (!product || *product > limit) {
    std::string shape;
    for (const std::uint64_t f : factors) shape += (shape.empty() ? "" : " x ") + std::to_string(f);
    throw InputError(fmt::format("{}: {} = {}{} exceeds the limit of {} ({})", file, field, shape,
                                 product ? fmt::format(" = {}", *product) : std::string(" (overflows 64 bits)"), limit,
                                 how_to_raise));
  }
  return *product;
}

std::uint64_t parseUnsignedStrict(const std::string& what, const std::string& text, std::uint64_t lo,
                                  std::uint64_t hi) {
  std::uint64_t v = 0;
  bool ok = !text.empty() && text.size() <= 20;
  for (const char c : text) {
    if (!ok) break;
    if (c < '0' || c > '9' || __builtin_mul_overflow(v, 10u, &v) ||
        __builtin_add_overflow(v, std::uint64_t(c - '0'), &v)) {
      ok = false;
    }
  }
  if (!ok || v < lo || v > hi) {
    throw UsageError(fmt::format("{} = \"{}\": expected a whole number in [{}, {}]", what, text, lo, hi));
  }
  return v;
}

std::uint64_t memoryBudgetBytesFromEnv() {
  const auto mb = env::get("NEPHELE_IO_MEMORY_BUDGET_MB");
  if (!mb) return kDefaultMemoryBudgetBytes;
  return parseUnsignedStrict("NEPHELE_IO_MEMORY_BUDGET_MB (MiB)", *mb, 1, kMaxMemoryBudgetMiB) << 20;
}

std::uint64_t hdf5OpenTimeoutSecondsFromEnv() {
  const auto s = env::get("NEPHELE_HDF5_OPEN_TIMEOUT_S");
  if (!s) return 300;
  return parseUnsignedStrict("NEPHELE_HDF5_OPEN_TIMEOUT_S (seconds)", *s, 1, 86400);
}

}  // namespace nph::limits
