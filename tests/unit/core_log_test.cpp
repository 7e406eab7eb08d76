#include <gtest/gtest.h>

#include "core/env.h"
#include "core/error.h"
#include "core/log.h"

#include <cstdlib>

TEST(CoreEnv, UnsetAndEmptyAreNullopt) {
  ::setenv("NEPHELE_TEST_ENV", "", 1);
  EXPECT_FALSE(nph::env::get("NEPHELE_TEST_ENV").has_value());
  ::setenv("NEPHELE_TEST_ENV", "x", 1);
  EXPECT_EQ(nph::env::get("NEPHELE_TEST_ENV").value(), "x");
  ::unsetenv("NEPHELE_TEST_ENV");
  EXPECT_FALSE(nph::env::get("NEPHELE_TEST_ENV").has_value());
}

TEST(CoreLog, ThresholdFiltersBelowLevel) {
  const auto saved = nph::log::threshold();
  nph::log::setThreshold(nph::log::Level::Warn);
  EXPECT_EQ(nph::log::threshold(), nph::log::Level::Warn);
  testing::internal::CaptureStderr();
  nph::log::info("hidden {}", 1);
  nph::log::warn("shown {}", 2);
  const std::string out = testing::internal::GetCapturedStderr();
  nph::log::setThreshold(saved);
  EXPECT_EQ(out.find("hidden"), std::string::npos);
  EXPECT_NE(out.find("nephele[warn] shown 2"), std::string::npos);
}

TEST(CoreError, HierarchyCatchesAsBase) {
  try {
    throw nph::InputError("f.nc: QCLOUD has 3 dims, expected 4");
  } catch (const nph::Error& e) {
    EXPECT_STREQ(e.what(), "f.nc: QCLOUD has 3 dims, expected 4");
  }
}
