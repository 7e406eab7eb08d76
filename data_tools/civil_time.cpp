#include "civil_time.h"

#include <fmt/format.h>

namespace nph::datagen {
namespace {

std::int64_t daysFromCivil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const auto yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

void civilFromDays(std::int64_t z, int& year, int& month, int& day) {
  z += 719468;
  const std::int64_t era = (z >= 0 ? z : z - 146096) / 146097;
  const auto doe = static_cast<unsigned>(z - era * 146097);
  const unsigned yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
  const std::int64_t y = static_cast<std::int64_t>(yoe) + era * 400;
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  const unsigned d = doy - (153 * mp + 2) / 5 + 1;
  const unsigned m = mp < 10 ? mp + 3 : mp - 9;
  year = static_cast<int>(y + (m <= 2));
  month = static_cast<int>(m);
  day = static_cast<int>(d);
}

}  // namespace

CivilTime addHours(const CivilTime& t, std::int64_t hours) {
  const std::int64_t days = daysFromCivil(t.year, static_cast<unsigned>(t.month), static_cast<unsigned>(t.day));
  std::int64_t total_hours = days * 24 + t.hour + hours;
  std::int64_t new_days = total_hours >= 0 ? total_hours / 24 : (total_hours - 23) / 24;
  CivilTime out = t;
  out.hour = static_cast<int>(total_hours - new_days * 24);
  civilFromDays(new_days, out.year, out.month, out.day);
  return out;
}

std::string wrfTimeString(const CivilTime& t) {
  return fmt::format("{:04d}-{:02d}-{:02d}_{:02d}:{:02d}:{:02d}", t.year, t.month, t.day, t.hour,
                     t.minute, t.second);
}

int dayOfYear(const CivilTime& t) {
  return static_cast<int>(daysFromCivil(t.year, static_cast<unsigned>(t.month), static_cast<unsigned>(t.day)) -
                          daysFromCivil(t.year, 1, 1)) + 1;
}

}  // namespace nph::datagen
