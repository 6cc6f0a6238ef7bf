#pragma once
// Eclipses by the central body (the Earth, the Moon, a planet): the sunlit fraction of the
// solar disc seen from the spacecraft, with umbra and penumbra (two discs of apparent radii
// a (Sun) and b (the body) at angular
// separation c: lit = 1 − overlap/(π a²)), and the times where the spacecraft enters and
// leaves the penumbra and the umbra, found by root bracketing to 1 ms.
#include "orbits/orbit.hpp"

#include <Eigen/Dense>

#include <vector>

namespace radnet::orbits {

/// Fraction of the solar disc visible, 0 (umbra) … 1 (full Sun).
/// @param sat_eci   spacecraft position, m
/// @param sun_eci   Sun position (direction × distance), m
/// @param earth_radius_m  the occulting sphere's radius (a spherical body of its equatorial radius)
double sunlitFraction(const Eigen::Vector3d& sat_eci, const Eigen::Vector3d& sun_eci, double earth_radius_m);

/// An eclipse event of one orbit.
struct EclipseEvent {
  enum Kind { PenumbraEntry, UmbraEntry, UmbraExit, PenumbraExit } kind;
  double t_s;  ///< seconds after the epoch
};

/// Every penumbra/umbra entry and exit in [t0, t1], in time order. Sampled at steps of
/// period/720 (each shadow phase lasts about that long or longer in low orbits; the sign-change test misses only a grazing eclipse shorter than a step), then each sign
/// change of the shadow-boundary functions is refined by bisection to 1 ms.
std::vector<EclipseEvent> eclipseEvents(const Orbit& orbit, double t0_s, double t1_s);

/// Sun position (m, ECI) at t seconds after the orbit's epoch.
Eigen::Vector3d sunEci(const Orbit& orbit, double t_s);

}  // namespace radnet::orbits
