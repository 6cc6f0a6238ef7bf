#pragma once
// Sweep positions along an orbit: P positions per orbit, evenly spaced in time (or in
// argument of latitude) over one or several nodal periods (Orbit::nodalPeriod), plus every eclipse entry and exit inserted exactly, so transitions
// are resolved without a fine grid.
#include "orbits/attitude.hpp"
#include "orbits/eclipse.hpp"

#include <Eigen/Dense>

#include <vector>

namespace radnet::orbits {

struct SweepOptions {
  enum class Spacing { Time, TrueAnomaly } spacing = Spacing::Time;
  int positions_per_orbit = 72;
  double orbits = 1.0;
  bool insert_eclipse_events = true;
  double solar_constant_w_m2 = 1361.0;  ///< at 1 AU (Kopp & Lean 2011, TSI at solar minimum)
};

struct SweepPosition {
  double t_s = 0.0;               ///< seconds after the epoch
  Eigen::Vector3d sun_body;       ///< unit, body frame
  Eigen::Vector3d planet_body;      ///< unit, towards the central body's centre (the Earth's unless orbit.body), body frame
  double planet_distance_m = 0.0;  ///< to the central body's centre, m
  double sunlit_fraction = 1.0;   ///< 0 … 1
  double beta_rad = 0.0;
  double solar_flux_w_m2 = 0.0;  ///< at the spacecraft's Sun distance, before the eclipse factor
  bool event = false;            ///< an inserted eclipse entry/exit
  Eigen::Matrix3d body_from_eci;
  Eigen::Vector3d position_eci_m;
  Eigen::Vector3d velocity_eci_m_s;
  KeplerElements elements;  ///< the propagator's elements at t (Orbit::elementsAt)
};

/// @throws OrbitError on invalid options
std::vector<SweepPosition> sweepOrbit(const Orbit& orbit, const AttitudeSpec& attitude, const SweepOptions& options);

}  // namespace radnet::orbits
