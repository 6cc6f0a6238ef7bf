#pragma once
// Astronomical constants and time. The Earth's own constants (GeographicLib's WGS84) are
// orbits/body.hpp's CentralBody::earth().
#include <string>

namespace radnet::orbits {

inline constexpr double kAstronomicalUnit = 149597870700.0;  ///< m (IAU 2012, exact)
inline constexpr double kSunRadius = 6.957e8;                ///< nominal solar radius, m (IAU 2015)
inline constexpr double kSecondsPerDay = 86400.0;
inline constexpr double kJ2000 = 2451545.0;  ///< Julian date of J2000.0

/// Julian date (UTC) of an ISO 8601 time "YYYY-MM-DDThh:mm:ss[.fff][Z]" (UTC only; a date
/// alone means midnight). @throws std::invalid_argument naming what is malformed
double julianDateFromIso(const std::string& iso);

/// ISO 8601 UTC text of a Julian date (to the second).
std::string isoFromJulianDate(double jd);

}  // namespace radnet::orbits
