#pragma once
// Two-body orbits with the secular J2 drift of the node and the argument of perigee
// (and of the mean anomaly), as ESATAN / Thermal Desktop users define them.
#include "orbits/body.hpp"
#include "orbits/earth.hpp"

#include <Eigen/Dense>

#include <stdexcept>

namespace radnet::orbits {

/// A caller mistake in orbit data; the message names the bad value.
class OrbitError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Classical elements at the epoch. Angles in radians, a in metres.
struct KeplerElements {
  double semi_major_axis_m = 0.0;
  double eccentricity = 0.0;
  double inclination_rad = 0.0;
  double raan_rad = 0.0;  ///< right ascension of the ascending node
  double arg_perigee_rad = 0.0;
  double true_anomaly_rad = 0.0;  ///< at the epoch
};

struct OrbitState {
  Eigen::Vector3d position_eci_m;
  Eigen::Vector3d velocity_eci_m_s;
};

/// Osculating two-body elements of a state for the gravitational parameter μ (m³/s²)
/// (Vallado, Algorithm 9, RV2COE). Angles in [0, 2π); an undefined node or perigee (equatorial
/// or circular orbit) is 0 and the angle it would measure from moves to the next defined one.
/// @throws OrbitError for a state that is not a bound ellipse
KeplerElements elementsFromState(const OrbitState& state, double mu_m3_s2);

/// Solves Kepler's equation M = E − e sin E for E (e in [0, 1)), to 1e-15 rad.
/// Newton from a starting value that converges for every M and e < 1 (Danby's E₀ = M + 0.85 e sign(sin M)).
double solveKepler(double mean_anomaly_rad, double eccentricity);

class Orbit {
 public:
  /// @throws OrbitError for e ≥ 1, a perigee below the body's surface, or non-finite values
  Orbit(const KeplerElements& elements, double epoch_jd, const CentralBody& body = CentralBody::earth());

  /// Position and velocity t seconds after the epoch (two-body + secular J2).
  OrbitState state(double t_s) const;
  /// The elements state(t) is computed from: a and e as at the epoch, Ω and ω drifted at the
  /// secular J2 rates, the true anomaly reached at t. They are the osculating elements of
  /// state(t) for the gravitational parameter n̄² a³ (n̄ the J2-corrected mean motion).
  KeplerElements elementsAt(double t_s) const;
  /// Anomalistic period of the unperturbed orbit, 2π √(a³/GM), s.
  double period() const;
  /// Nodal (draconic) period, s: ascending node to ascending node under the secular J2
  /// rates, 2π / (n̄ + ω̇) with n̄ the J2-corrected mean motion. One sweep orbit spans it,
  /// so the swept orbit closes in argument of latitude (Vallado, §9.6).
  double nodalPeriod() const;
  /// Mean motion including the secular J2 correction, rad/s.
  double meanMotion() const { return mean_motion_; }
  double epochJd() const { return epoch_jd_; }
  const KeplerElements& elements() const { return el_; }
  /// Secular rates from J2, rad/s.
  double raanRate() const { return raan_rate_; }
  double argPerigeeRate() const { return argp_rate_; }
  /// Seconds after the epoch at which the true anomaly first reaches ν (rad) after the
  /// epoch's true anomaly has advanced by `turns` full revolutions (0: the first orbit).
  double timeOfTrueAnomaly(double nu_rad, int turns) const;
  /// Orbit normal (unit angular momentum) in ECI at time t.
  Eigen::Vector3d normal(double t_s) const;
  const CentralBody& body() const { return body_; }

 private:
  KeplerElements el_;
  double epoch_jd_;
  CentralBody body_;
  double mean_motion_ = 0.0;  ///< rad/s, including the J2 secular correction
  double m0_ = 0.0;           ///< mean anomaly at the epoch
  double raan_rate_ = 0.0, argp_rate_ = 0.0;
};

/// Circular orbit from altitude above the equatorial radius, inclination and RAAN (deg).
KeplerElements circularElements(double altitude_m, double inclination_deg, double raan_deg,
                                double arg_latitude_deg = 0.0, const CentralBody& body = CentralBody::earth());

/// Elements from perigee/apogee altitudes.
KeplerElements perigeeApogeeElements(double perigee_altitude_m, double apogee_altitude_m, double inclination_deg,
                                     double raan_deg, double arg_perigee_deg, double true_anomaly_deg,
                                     const CentralBody& body = CentralBody::earth());

/// Inclination (deg) making a circular orbit sun-synchronous: its node drifts 360° per
/// tropical year, cos i = −2 Ω̇ a^{7/2} / (3 J2 R² √GM).
double sunSynchronousInclinationDeg(double altitude_m, const CentralBody& body = CentralBody::earth());

/// RAAN (deg) that puts the ascending node at a local mean solar time (hours) at the epoch.
double raanForLocalTimeDeg(double ltan_hours, double epoch_jd, const CentralBody& body = CentralBody::earth());

/// Circular orbit whose plane makes angle beta with the Sun direction at the epoch
/// (orbit normal n with asin(n·s) = β); the node is placed where the Sun's meridian
/// crosses the equator, so the orbit noon is at the epoch's Sun side.
KeplerElements betaElements(double altitude_m, double beta_deg, double epoch_jd,
                            const CentralBody& body = CentralBody::earth());

/// Beta angle: the angle between the orbit plane and the Sun direction, rad.
double betaAngle(const Orbit& orbit, double t_s);

}  // namespace radnet::orbits
