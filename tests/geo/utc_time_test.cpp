// geo::UtcTime: ISO 8601 / WRF parsing, ISO 8601 out, the proleptic Gregorian calendar (Hinnant's
// days_from_civil / civil_from_days) and arithmetic in seconds.
#include "geo/utc_time.h"

#include <gtest/gtest.h>

#include <string>

#include "core/error.h"

namespace nph::geo {
namespace {

TEST(UtcTime, ParsesIsoAndWrfForms) {
  const double jd = UtcTime::parse("2026-09-01T12:00:00Z").julian_day;
  EXPECT_DOUBLE_EQ(jd, 2461285.0);  // 2026-09-01 12:00 UT
  EXPECT_DOUBLE_EQ(UtcTime::parse("2026-09-01_12:00:00").julian_day, jd);
  EXPECT_DOUBLE_EQ(UtcTime::parse("2026-09-01 12:00").julian_day, jd);
  EXPECT_DOUBLE_EQ(UtcTime::parse("2026-09-01T14:00:00+02:00").julian_day, jd);
  EXPECT_DOUBLE_EQ(UtcTime::parse("2026-09-01T12:00:00").julian_day, jd);
  EXPECT_NEAR(UtcTime::parse("2026-09-01T12:00:00.5Z").julian_day, jd + 0.5 / 86400.0, 1e-9);
  EXPECT_DOUBLE_EQ(UtcTime::parse("2026-09-01").julian_day, jd - 0.5);
  EXPECT_EQ(UtcTime::parse("2026-09-01_12:00:00").iso8601(), "2026-09-01T12:00:00Z");
  EXPECT_EQ(UtcTime::parse("2024-02-29T23:59:59Z").iso8601(), "2024-02-29T23:59:59Z");
  EXPECT_NEAR(UtcTime::parse("2026-09-01T18:30:00Z").utcHourOfDay(), 18.5, 1e-6);
  EXPECT_EQ(UtcTime::parse("2026-09-01T24:00:00Z").iso8601(), "2026-09-02T00:00:00Z");
}

TEST(UtcTime, RejectsMalformedTimesNamingThem) {
  for (const char* bad : {"", "2026-9-01T12:00:00Z", "2026-09-01X12:00", "2026-13-01T00:00:00Z", "2026-02-29T00:00:00Z",
                          "2026-09-01T12:60:00Z", "2026-09-01T12:00:00Q", "2026-09-01T12:00:00Z trailing", "yesterday",
                          "2026-09-01T24:30:00Z"}) {
    try {
      (void)UtcTime::parse(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad + "'"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("YYYY-MM-DD"), std::string::npos) << e.what();
    }
  }
}

TEST(UtcTime, CalendarMatchesKnownDayCounts) {
  // Day counts since 1970-01-01 that anyone can check: the epoch itself, 2000-03-01 (11017 days:
  // 30 years of which 7 leap years, plus January and a leap February 2000), and a date before it.
  EXPECT_EQ(daysFromCivil(1970, 1, 1), 0);
  EXPECT_EQ(daysFromCivil(2000, 3, 1), 30 * 365 + 7 + 31 + 29);
  EXPECT_EQ(daysFromCivil(1969, 12, 31), -1);
  for (const std::int64_t days : {std::int64_t{-719468}, std::int64_t{-1}, std::int64_t{0}, std::int64_t{11016},
                                  std::int64_t{20697}, std::int64_t{2932896}}) {
    int y = 0, m = 0, d = 0;
    civilFromDays(days, y, m, d);
    EXPECT_EQ(daysFromCivil(y, unsigned(m), unsigned(d)), days) << y << "-" << m << "-" << d;
  }
  EXPECT_EQ(daysInMonth(2024, 2), 29);
  EXPECT_EQ(daysInMonth(2100, 2), 28);  // not a leap year (divisible by 100, not by 400)
  EXPECT_EQ(daysInMonth(2000, 2), 29);
  EXPECT_EQ(daysInMonth(2026, 9), 30);
}

TEST(UtcTime, WritesIsoWrfAndCivilForms) {
  const UtcTime t = UtcTime::fromCivil(2026, 9, 1, 12, 30, 15.0);
  EXPECT_EQ(t.iso8601(), "2026-09-01T12:30:15Z");
  EXPECT_EQ(t.wrfTimeString(), "2026-09-01_12:30:15");
  EXPECT_EQ(UtcTime::parse(t.wrfTimeString()).iso8601(), t.iso8601());
  const CivilTime c = t.civil();
  EXPECT_EQ(c.year, 2026);
  EXPECT_EQ(c.month, 9);
  EXPECT_EQ(c.day, 1);
  EXPECT_EQ(c.hour, 12);
  EXPECT_EQ(c.minute, 30);
  EXPECT_EQ(c.second, 15);
  // Day of the year (WRF's JULDAY): 1 September is day 244 in 2026 and day 245 in leap 2024.
  EXPECT_EQ(t.dayOfYear(), 244);
  EXPECT_EQ(UtcTime::fromCivil(2024, 9, 1).dayOfYear(), 245);
  EXPECT_EQ(UtcTime::fromCivil(2026, 1, 1).dayOfYear(), 1);
  EXPECT_EQ(UtcTime::fromCivil(2024, 12, 31, 23, 59, 59.0).dayOfYear(), 366);
  EXPECT_THROW((void)UtcTime::fromCivil(2026, 2, 29), InputError);
}

TEST(UtcTime, ArithmeticInSeconds) {
  const UtcTime t0 = UtcTime::parse("2026-12-31T23:00:00Z");
  // Across a year boundary, and backwards.
  EXPECT_EQ(t0.plusSeconds(5400.0).iso8601(), "2027-01-01T00:30:00Z");
  EXPECT_EQ(t0.plusSeconds(-86400.0 * 365).iso8601(), "2025-12-31T23:00:00Z");
  // 2024-02-28 to 2024-03-01 is two days in a leap year.
  EXPECT_EQ(UtcTime::parse("2024-03-01T00:00:00Z").secondsSince(UtcTime::parse("2024-02-28T00:00:00Z")), 2.0 * 86400.0);
  // Whole milliseconds exactly, whatever the Julian Day rounding (~40 µs): a step of 1/3 h
  // summed three times lands exactly on the hour.
  UtcTime t = t0;
  for (int k = 0; k < 3; ++k) t = t.plusSeconds(1200.0);
  EXPECT_EQ(t.secondsSince(t0), 3600.0);
  EXPECT_EQ(t0.plusSeconds(0.25).secondsSince(t0), 0.25);
  EXPECT_EQ(t0.secondsSince(t0.plusSeconds(90.0)), -90.0);
  // Generator use: whole hours after a start, written as WRF writes them.
  const UtcTime start = UtcTime::fromCivil(2026, 9, 1, 12);
  EXPECT_EQ(start.plusSeconds(3600.0 * 13).wrfTimeString(), "2026-09-02_01:00:00");
}

}  // namespace
}  // namespace nph::geo
