#pragma once
// Proleptic Gregorian calendar arithmetic for timestamps written by the generators
// (days_from_civil / civil_from_days after H. Hinnant, "chrono-compatible low-level date algorithms").
#include <cstdint>
#include <string>

namespace nph::datagen {

struct CivilTime {
  int year = 2026, month = 1, day = 1, hour = 0, minute = 0, second = 0;
};

CivilTime addHours(const CivilTime& t, std::int64_t hours);
/// WRF `Times` string: "2026-09-01_12:00:00" (19 characters).
std::string wrfTimeString(const CivilTime& t);
/// Day of the year, 1 = 1 January (WRF global attribute JULDAY).
int dayOfYear(const CivilTime& t);

}  // namespace nph::datagen
