#pragma once
// Proleptic Gregorian calendar <-> days since 1970-01-01 (H. Hinnant, "chrono-Compatible
// Low-Level Date Algorithms": days_from_civil, civil_from_days). Shared by the solar position,
// time parsing and the sample-data generators.
#include <cstdint>

namespace nph::civil {

std::int64_t daysFromCivil(std::int64_t year, unsigned month, unsigned day);
void civilFromDays(std::int64_t days, int& year, int& month, int& day);

}  // namespace nph::civil
