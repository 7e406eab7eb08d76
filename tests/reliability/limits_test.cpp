// The resource limits and their arithmetic (core/limits.h): overflow-checked products, casts that
// are range-checked before they happen, and strictly parsed environment values.
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/error.h"
#include "core/limits.h"
#include "io/load_options.h"
#include "reliability_support.h"

namespace nph::reliability {
namespace {

TEST(Limits, ProductsOverflowingSixtyFourBitsAreDetected) {
  EXPECT_EQ(limits::checkedProduct({2, 3, 7}), 42u);
  // nx = ny = 2^30, nz = 4, 4 bytes per voxel: 2^64 wrapped to 0 before.
  EXPECT_FALSE(limits::checkedProduct({1u << 30, 1u << 30, 4, 4}).has_value());
  expectError<InputError>(
      [] {
        (void)limits::requireProductWithin("f.nph", "grid", {1u << 30, 1u << 30, 16}, limits::kMaxGridPoints,
                                           "raise it");
      },
      {"f.nph: grid = 1073741824 x 1073741824 x 16 (overflows 64 bits) exceeds the limit of 2147483648 (raise it)"});
  EXPECT_EQ(limits::requireProductWithin("f", "g", {1000, 1000}, 1000000, ""), 1000000u);
}

TEST(Limits, FloatToIntConversionsAreCheckedBeforeTheCast) {
  EXPECT_EQ(limits::toIntChecked<int>(-2147483648.0), std::numeric_limits<int>::min());
  EXPECT_EQ(limits::toIntChecked<int>(2147483647.0), std::numeric_limits<int>::max());
  EXPECT_FALSE(limits::toIntChecked<int>(2147483648.0));
  EXPECT_FALSE(limits::toIntChecked<int>(1e20));
  EXPECT_FALSE(limits::toIntChecked<int>(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(limits::toIntChecked<int>(-std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(limits::toIntChecked<std::uint32_t>(-1.0));
  EXPECT_EQ(limits::toIntChecked<std::uint32_t>(4294967295.0), 4294967295u);
  EXPECT_FALSE(limits::toIntChecked<std::int64_t>(9.3e18));
}

/// Sets an environment variable for the scope of a test.
struct ScopedEnv {
  ScopedEnv(const char* name, const char* value) : name_(name) { ::setenv(name, value, 1); }
  ~ScopedEnv() { ::unsetenv(name_); }
  const char* name_;
};

TEST(Limits, MemoryBudgetFromTheEnvironmentIsParsedStrictly) {
  {
    const ScopedEnv env("NEPHELE_IO_MEMORY_BUDGET_MB", "512");
    EXPECT_EQ(limits::memoryBudgetBytesFromEnv(), 512u << 20);
    EXPECT_EQ(io::memoryBudgetBytes(io::LoadOptions{}), std::size_t(512) << 20);
  }
  EXPECT_EQ(limits::memoryBudgetBytesFromEnv(), limits::kDefaultMemoryBudgetBytes);
  // Huge values overflowed to 0 (MiB << 20), garbage was ignored: both are errors now.
  for (const char* bad :
       {"abc", "12abc", "0", "-5", " 5", "1e3", "99999999999999999999999", "18446744073709551615", "16777217"}) {
    SCOPED_TRACE(bad);
    const ScopedEnv env("NEPHELE_IO_MEMORY_BUDGET_MB", bad);
    expectError<UsageError>([] { (void)limits::memoryBudgetBytesFromEnv(); },
                            {"NEPHELE_IO_MEMORY_BUDGET_MB", "expected a whole number in [1, 16777216]"});
  }
}

}  // namespace
}  // namespace nph::reliability
