#pragma once
// Physical constants and unit conversions, spelled once for every stage. Header-only
// and dependency-free, so geometry/ and orbits/ may include it as well as solver/ and
// cases/ (docs/design.md, "Dependencies").
#include <cmath>

namespace radnet::units {

/// Stefan–Boltzmann constant σ, W m⁻² K⁻⁴ (CODATA 2018, exact in SI since 2019).
inline constexpr double kStefanBoltzmann = 5.670374419e-8;

/// Radians per degree.
inline constexpr double kRadPerDeg = M_PI / 180.0;

/// @param deg angle, degrees @return radians
inline constexpr double degToRad(double deg) { return deg * kRadPerDeg; }

/// @param rad angle, radians @return degrees
inline constexpr double radToDeg(double rad) { return rad / kRadPerDeg; }

}  // namespace radnet::units
