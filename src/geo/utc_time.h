#pragma once
// One UTC time type for nephele: parsed once from ISO 8601 (or WRF's "YYYY-MM-DD_hh:mm:ss"),
// written back as ISO 8601, with arithmetic in seconds. The solar position (scene/), the animation
// clock (engine/), the loaders (io/) and the sample-data generators (data_tools/) all use it.
//
// Representation: a Julian Day (UT), days since -4712-01-01 12:00 UT, as the solar position of
// Meeus 1998 ch. 25 wants it. A double carries ~40 µs of rounding at today's Julian Days (ulp of
// 2.46e6 days), so times are written to the nearest whole second and differences are rounded to
// whole milliseconds (secondsSince).
//
// Calendar: proleptic Gregorian, after H. Hinnant, "chrono-Compatible Low-Level Date Algorithms"
// (days_from_civil, civil_from_days). No leap seconds (UTC as POSIX time counts it).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace nph::geo {

/// Days since 1970-01-01 of a proleptic Gregorian date (Hinnant's days_from_civil).
std::int64_t daysFromCivil(std::int64_t year, unsigned month, unsigned day);
/// The date of a day count since 1970-01-01 (Hinnant's civil_from_days).
void civilFromDays(std::int64_t days, int& year, int& month, int& day);
/// 28..31 for a month 1..12 of the proleptic Gregorian calendar.
int daysInMonth(int year, int month);

/// Broken-down UTC time, whole seconds.
struct CivilTime {
  int year = 1970, month = 1, day = 1, hour = 0, minute = 0, second = 0;
};

struct UtcTime {
  double julian_day = 2451545.0;  ///< J2000.0 = 2000-01-01T12:00:00Z

  /// Parses ISO 8601 ("2026-09-01T12:00:00Z", "2026-09-01T12:00:00.5+02:00", "2026-09-01 12:00")
  /// and WRF's "2026-09-01_12:00:00". Without a zone designator the time is taken as UTC (WRF and
  /// ICON write UTC). Throws InputError naming `text` and the expected form.
  static UtcTime parse(std::string_view text);
  /// InputError when the date or time of day does not exist (hour 24 only as 24:00:00).
  static UtcTime fromCivil(int year, int month, int day, int hour = 0, int minute = 0, double second = 0.0);

  /// "YYYY-MM-DDThh:mm:ssZ" (seconds rounded to the nearest whole second).
  std::string iso8601() const;
  /// WRF's `Times` form "YYYY-MM-DD_hh:mm:ss" (19 characters, no zone: WRF writes UTC).
  std::string wrfTimeString() const;
  /// The civil date and time, rounded to the nearest whole second (as iso8601() writes it).
  CivilTime civil() const;
  /// Day of the year, 1 = 1 January (WRF's JULDAY).
  int dayOfYear() const;
  /// Hours since 00:00 UTC of the same civil day, in [0, 24).
  double utcHourOfDay() const;

  /// This time `seconds` later (earlier when negative).
  UtcTime plusSeconds(double seconds) const;
  /// Seconds from `earlier` to this time, rounded to whole milliseconds: the Julian Days carry
  /// ~40 µs of rounding, which must not move a time that falls exactly on another (a timestep, a
  /// frame) to the other side of it.
  double secondsSince(const UtcTime& earlier) const;

  friend bool operator==(const UtcTime&, const UtcTime&) = default;
  friend auto operator<=>(const UtcTime&, const UtcTime&) = default;
};

/// A time that a file may not carry (loaders, volumes, caches store std::optional<UtcTime>).
using OptionalUtcTime = std::optional<UtcTime>;

/// iso8601() of a present time, "" of an absent one: the form file formats (the .nph index,
/// OpenVDB metadata, the C API) and messages use.
std::string isoOrEmpty(const OptionalUtcTime& time);
/// The inverse: "" is no time, anything else must parse (InputError naming the text otherwise).
OptionalUtcTime parseOptional(std::string_view text);

}  // namespace nph::geo
