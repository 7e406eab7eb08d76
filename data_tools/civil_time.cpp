#include "civil_time.h"

#include <fmt/format.h>

#include "core/civil_date.h"

namespace nph::datagen {
namespace {

using civil::civilFromDays;
using civil::daysFromCivil;

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
