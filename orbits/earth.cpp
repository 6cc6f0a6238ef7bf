#include "orbits/earth.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace radnet::orbits {

double julianDateFromIso(const std::string& iso) {
  int y = 0, mo = 0, d = 0, h = 0, mi = 0;
  double s = 0.0;
  char tail[8] = {0}, date_tail[8] = {0};
  const int n = std::sscanf(iso.c_str(), "%4d-%2d-%2dT%2d:%2d:%lf%7s", &y, &mo, &d, &h, &mi, &s, tail);
  const bool date_only = iso.size() == 10 && std::sscanf(iso.c_str(), "%4d-%2d-%2d%7s", &y, &mo, &d, date_tail) == 3;
  if (!date_only && !(n == 6 || (n == 7 && std::string(tail) == "Z")))
    throw std::invalid_argument("'" + iso + "' is not an ISO 8601 UTC time; expected YYYY-MM-DDThh:mm:ssZ");
  if (date_only) h = mi = 0, s = 0.0;
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || !(s >= 0 && s < 61) || y < 1900 || y > 2200)
    throw std::invalid_argument("'" + iso +
                                "' has a field out of range (year 1900–2200, month, day, hour, minute, second)");
  // The days of each month, Gregorian leap years: 2026-02-30 is no date.
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  if (d > kDays[mo - 1] + (mo == 2 && leap ? 1 : 0))
    throw std::invalid_argument("'" + iso + "' names day " + std::to_string(d) + " of a month that has " +
                                std::to_string(kDays[mo - 1] + (mo == 2 && leap ? 1 : 0)) + " days");
  // Fliegel & Van Flandern (1968): Julian day number of a Gregorian date.
  const int a = (14 - mo) / 12, yy = y + 4800 - a, mm = mo + 12 * a - 3;
  const long jdn = d + (153 * mm + 2) / 5 + 365L * yy + yy / 4 - yy / 100 + yy / 400 - 32045;
  return double(jdn) - 0.5 + (h + (mi + s / 60.0) / 60.0) / 24.0;
}

std::string isoFromJulianDate(double jd) {
  const double z = std::floor(jd + 0.5);
  double frac = jd + 0.5 - z;
  long a = static_cast<long>(z);
  const long alpha = static_cast<long>((a - 1867216.25) / 36524.25);
  a += 1 + alpha - alpha / 4;
  const long b = a + 1524, c = static_cast<long>((b - 122.1) / 365.25), dd = static_cast<long>(365.25 * c);
  const long e = static_cast<long>((b - dd) / 30.6001);
  const int day = static_cast<int>(b - dd - static_cast<long>(30.6001 * e));
  const int month = static_cast<int>(e < 14 ? e - 1 : e - 13);
  const int year = static_cast<int>(month > 2 ? c - 4716 : c - 4715);
  long secs = std::lround(frac * 86400.0);
  char buf[64];  // room for any int year and long fields, so nothing is ever cut
  std::snprintf(buf, sizeof buf, "%04d-%02d-%02dT%02ld:%02ld:%02ldZ", year, month, day, secs / 3600, (secs / 60) % 60,
                secs % 60);
  return buf;
}

}  // namespace radnet::orbits
