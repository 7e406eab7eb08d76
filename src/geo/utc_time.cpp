#include "geo/utc_time.h"

#include <fmt/format.h>

#include <cctype>
#include <cmath>

#include "core/error.h"

namespace nph::geo {
namespace {

constexpr double kJulianDayUnixEpoch = 2440587.5;  ///< JD of 1970-01-01T00:00:00Z
constexpr double kSecondsPerDay = 86400.0;

bool isLeap(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

class TimeParser {
 public:
  explicit TimeParser(std::string_view text) : s_(text) {}
  [[noreturn]] void fail() const {
    throw InputError(
        fmt::format("time '{}': expected a UTC time as ISO 8601 'YYYY-MM-DDThh:mm:ss[.fff][Z|±hh:mm]' or WRF "
                    "'YYYY-MM-DD_hh:mm:ss'",
                    s_));
  }
  int digits(int n) {
    int v = 0;
    for (int k = 0; k < n; ++k, ++pos_) {
      if (pos_ >= s_.size() || !std::isdigit(static_cast<unsigned char>(s_[pos_]))) fail();
      v = v * 10 + (s_[pos_] - '0');
    }
    return v;
  }
  void expect(char c) {
    if (pos_ >= s_.size() || s_[pos_] != c) fail();
    ++pos_;
  }
  bool accept(char c) {
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  bool done() const { return pos_ >= s_.size(); }
  double fraction() {  // after '.' : digits as a fraction of one
    double scale = 0.1, v = 0.0;
    const std::size_t start = pos_;
    while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) {
      v += scale * (s_[pos_] - '0');
      scale *= 0.1;
      ++pos_;
    }
    if (pos_ == start) fail();
    return v;
  }

 private:
  std::string_view s_;
  std::size_t pos_ = 0;
};

}  // namespace

std::int64_t daysFromCivil(std::int64_t y, unsigned m, unsigned d) {
  y -= m <= 2 ? 1 : 0;
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
  const unsigned doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
  const unsigned mp = (5 * doy + 2) / 153;
  day = static_cast<int>(doy - (153 * mp + 2) / 5 + 1);
  month = static_cast<int>(mp < 10 ? mp + 3 : mp - 9);
  year = static_cast<int>(static_cast<std::int64_t>(yoe) + era * 400 + (month <= 2 ? 1 : 0));
}

int daysInMonth(int y, int m) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return m == 2 && isLeap(y) ? 29 : kDays[m - 1];
}

UtcTime UtcTime::fromCivil(int year, int month, int day, int hour, int minute, double second) {
  if (month < 1 || month > 12 || day < 1 || day > daysInMonth(year, month) || hour < 0 || hour > 24 ||
      (hour == 24 && (minute > 0 || second > 0.0)) || minute < 0 || minute > 59 || !(second >= 0.0) ||
      !(second < 61.0)) {
    throw InputError(fmt::format("time {:04}-{:02}-{:02} {:02}:{:02}:{}: not a valid calendar date "
                                 "and time of day",
                                 year, month, day, hour, minute, second));
  }
  const auto days = static_cast<double>(daysFromCivil(year, static_cast<unsigned>(month), static_cast<unsigned>(day)));
  const double dayFraction = (double(hour) + (double(minute) + second / 60.0) / 60.0) / 24.0;
  return UtcTime{kJulianDayUnixEpoch + days + dayFraction};
}

UtcTime UtcTime::parse(std::string_view text) {
  TimeParser p(text);
  const int year = p.digits(4);
  p.expect('-');
  const int month = p.digits(2);
  p.expect('-');
  const int day = p.digits(2);
  int hour = 0, minute = 0;
  double second = 0.0;
  int offsetMinutes = 0;
  if (!p.done()) {
    if (!(p.accept('T') || p.accept('_') || p.accept(' ') || p.accept('t'))) p.fail();
    hour = p.digits(2);
    p.expect(':');
    minute = p.digits(2);
    if (p.accept(':')) {
      second = p.digits(2);
      if (p.accept('.') || p.accept(',')) second += p.fraction();
    }
    if (p.accept('Z') || p.accept('z')) {
    } else if (!p.done()) {
      int sign = 0;
      if (p.accept('+')) sign = 1;
      else if (p.accept('-')) sign = -1;
      else p.fail();
      const int oh = p.digits(2);
      p.accept(':');
      const int om = p.done() ? 0 : p.digits(2);
      if (oh > 18 || om > 59) p.fail();
      offsetMinutes = sign * (oh * 60 + om);
    }
    if (!p.done()) p.fail();
  }
  try {
    UtcTime t = fromCivil(year, month, day, hour, minute, second);
    t.julian_day -= double(offsetMinutes) / (24.0 * 60.0);  // local = UTC + offset
    return t;
  } catch (const InputError&) {
    p.fail();
  }
}

CivilTime UtcTime::civil() const {
  const double unixSeconds = std::round((julian_day - kJulianDayUnixEpoch) * kSecondsPerDay);
  const auto s = static_cast<std::int64_t>(unixSeconds);
  std::int64_t days = s / 86400, rem = s % 86400;
  if (rem < 0) {
    rem += 86400;
    days -= 1;
  }
  CivilTime c;
  civilFromDays(days, c.year, c.month, c.day);
  c.hour = static_cast<int>(rem / 3600);
  c.minute = static_cast<int>((rem / 60) % 60);
  c.second = static_cast<int>(rem % 60);
  return c;
}

std::string UtcTime::iso8601() const {
  const CivilTime c = civil();
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z", c.year, c.month, c.day, c.hour, c.minute, c.second);
}

std::string UtcTime::wrfTimeString() const {
  const CivilTime c = civil();
  return fmt::format("{:04}-{:02}-{:02}_{:02}:{:02}:{:02}", c.year, c.month, c.day, c.hour, c.minute, c.second);
}

int UtcTime::dayOfYear() const {
  const CivilTime c = civil();
  return static_cast<int>(daysFromCivil(c.year, static_cast<unsigned>(c.month), static_cast<unsigned>(c.day)) -
                          daysFromCivil(c.year, 1, 1)) +
         1;
}

double UtcTime::utcHourOfDay() const {
  const double d = julian_day - kJulianDayUnixEpoch;
  return (d - std::floor(d)) * 24.0;
}

UtcTime UtcTime::plusSeconds(double seconds) const { return UtcTime{julian_day + seconds / kSecondsPerDay}; }

std::string isoOrEmpty(const OptionalUtcTime& time) { return time ? time->iso8601() : std::string(); }

OptionalUtcTime parseOptional(std::string_view text) {
  if (text.empty()) return std::nullopt;
  return UtcTime::parse(text);
}

double UtcTime::secondsSince(const UtcTime& earlier) const {
  return std::round((julian_day - earlier.julian_day) * kSecondsPerDay * 1000.0) / 1000.0;
}

}  // namespace nph::geo
