#pragma once
// The Sun: low-precision ephemeris of the Astronomical Almanac (section C, "Sun, low
// precision"), good to 0.01° in direction between 1950 and 2050, in the mean equator and
// equinox of date (taken as the ECI frame; precession since J2000 is 0.36° in 2026 and is
// common to every direction in the frame, so Sun–orbit geometry is unaffected).
#include <Eigen/Dense>

namespace radnet::orbits {

struct SunPosition {
  Eigen::Vector3d direction_eci;  ///< unit vector Earth → Sun
  double distance_m;
  double ecliptic_longitude_rad;
  double obliquity_rad;
};

/// @param jd Julian date (UTC; the 69 s to TT move the Sun by 0.0008°)
SunPosition sunPosition(double jd);

/// Declination of the Sun, degrees.
double sunDeclinationDeg(double jd);

/// Solar flux at a distance from the Sun, W/m²: solar_constant (at 1 AU) × (1 AU / r)².
double solarFlux(double solar_constant_w_m2, double distance_m);

}  // namespace radnet::orbits
