#pragma once
// Attitude: the rotation bodyFromEci at each position. One convention throughout: body
// vectors are the columns' images, v_body = bodyFromEci · v_eci.
//
// Modes (docs/orbits.md):
//  * nadir (LVLH): body +z towards the Earth's centre, +x along the velocity (its part
//    normal to +z), +y = z × x (so +y is the negative orbit normal).
//  * sun: body +z towards the Sun, +x as close as possible to the orbit normal.
//  * inertial: a fixed quaternion bodyFromEci (w, x, y, z).
//  * spin: inertial attitude turning about a body axis at a rate (deg/s) from a phase.
//  * pointing: primary body axis → primary target, secondary body axis as close as
//    possible to the secondary target (TRIAD); targets: sun, nadir, zenith, velocity,
//    orbit_normal, or a fixed ECI direction.
#include "orbits/orbit.hpp"

#include <Eigen/Geometry>

#include <string>

namespace radnet::orbits {

enum class Target { Sun, Nadir, Zenith, Velocity, OrbitNormal, Inertial };

struct PointingSpec {
  Eigen::Vector3d primary_body = Eigen::Vector3d::UnitZ();
  Target primary = Target::Nadir;
  Eigen::Vector3d primary_eci = Eigen::Vector3d::UnitZ();  ///< for Target::Inertial
  Eigen::Vector3d secondary_body = Eigen::Vector3d::UnitX();
  Target secondary = Target::Velocity;
  Eigen::Vector3d secondary_eci = Eigen::Vector3d::UnitX();
};

struct AttitudeSpec {
  enum class Mode { Nadir, Sun, Inertial, Spin, Pointing } mode = Mode::Nadir;
  Eigen::Quaterniond body_from_eci = Eigen::Quaterniond::Identity();  ///< inertial and spin (at t = 0)
  Eigen::Vector3d spin_axis_body = Eigen::Vector3d::UnitZ();
  double spin_rate_deg_s = 0.0;
  PointingSpec pointing;
};

/// The rotation taking ECI vectors to body vectors at time t.
/// @throws OrbitError when the two targets of a pointing are parallel at that time
Eigen::Matrix3d bodyFromEci(const AttitudeSpec& spec, const Orbit& orbit, const OrbitState& state,
                            const Eigen::Vector3d& sun_direction_eci, double t_s);

/// True when the Earth is fixed in the body frame for a circular orbit (nadir-type
/// attitudes), so planet rays can be cast once for the whole sweep.
bool earthFixedInBody(const AttitudeSpec& spec);

/// bodyFromEci R with R·b1 = a1 (the ECI target onto the body axis) and R·b2 as close to
/// a2 as possible (TRIAD).
Eigen::Matrix3d triad(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2, const Eigen::Vector3d& b1,
                      const Eigen::Vector3d& b2);

}  // namespace radnet::orbits
