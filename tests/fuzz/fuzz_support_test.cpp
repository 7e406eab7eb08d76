// The fuzz harness's own verdicts (tests/fuzz/fuzz_support.h): a user-facing refusal naming the
// input passes, everything else aborts the process, so a replay or a campaign cannot pass over a
// finding.
#include <gtest/gtest.h>

#include <new>
#include <stdexcept>
#include <string>

#include "fuzz_support.h"

namespace nph::fuzz {
namespace {

TEST(FuzzHarness, RefusalsNamingTheInputAreCleanOutcomes) {
  expectCleanOutcome("in.nc", [] {});
  expectCleanOutcome("in.nc", [] { throw InputError("in.nc: QCLOUD: expected 3 dimensions"); });
  expectCleanOutcome("in.nc", [] { throw UsageError("in.nc: width must be > 0"); });
  expectCleanOutcome("in.nc", [] { throw IoError("in.nc: read failed"); });
}

TEST(FuzzHarnessDeathTest, EverythingElseIsAFinding) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(expectCleanOutcome("in.nc", [] { throw std::bad_alloc(); }), "unexpected exception type");
  EXPECT_DEATH(expectCleanOutcome("in.nc", [] { throw std::length_error("vector::reserve"); }),
               "unexpected exception type: vector::reserve");
  EXPECT_DEATH(expectCleanOutcome("in.nc", [] { throw InputError("QCLOUD: expected 3 dimensions"); }),
               "InputError without the file name");
  EXPECT_DEATH(expectCleanOutcome("in.nc", [] { throw 42; }), "non-standard exception");
}

TEST(FuzzHarness, ScratchInputHoldsTheBytesAndIsRemoved) {
  std::filesystem::path where;
  {
    const std::string bytes = "CDF\x01 not really";
    const ScratchInput input(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "harness", ".nc");
    where = input.path();
    EXPECT_EQ(std::filesystem::file_size(where), bytes.size());
  }
  EXPECT_FALSE(std::filesystem::exists(where));
}

}  // namespace
}  // namespace nph::fuzz
