#include "orbits/sun.hpp"

#include "solver/units.hpp"

#include "orbits/earth.hpp"

#include <cmath>

namespace radnet::orbits {

SunPosition sunPosition(double jd) {
  constexpr double deg = units::kRadPerDeg;
  const double n = jd - kJ2000;                                                     // days from J2000.0
  const double L = (280.460 + 0.9856474 * n) * deg;                                 // mean longitude
  const double g = (357.528 + 0.9856003 * n) * deg;                                 // mean anomaly
  const double lambda = L + (1.915 * std::sin(g) + 0.020 * std::sin(2 * g)) * deg;  // ecliptic longitude
  const double eps = (23.439 - 0.0000004 * n) * deg;                                // obliquity of the ecliptic
  const double r_au = 1.00014 - 0.01671 * std::cos(g) - 0.00014 * std::cos(2 * g);
  SunPosition s;
  s.direction_eci =
      Eigen::Vector3d(std::cos(lambda), std::cos(eps) * std::sin(lambda), std::sin(eps) * std::sin(lambda));
  s.distance_m = r_au * kAstronomicalUnit;
  s.ecliptic_longitude_rad = lambda;
  s.obliquity_rad = eps;
  return s;
}

double sunDeclinationDeg(double jd) { return units::radToDeg(std::asin(sunPosition(jd).direction_eci.z())); }

double solarFlux(double solar_constant, double distance_m) {
  const double r = distance_m / kAstronomicalUnit;
  return solar_constant / (r * r);
}

}  // namespace radnet::orbits
