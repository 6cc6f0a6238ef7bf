#pragma once
// The central body a spacecraft orbits: the Earth (WGS84, from GeographicLib), the Moon,
// Mars, Venus, Mercury or Jupiter. Each brings its gravity (μ, equatorial radius, J2,
// rotation), its orientation (the IAU pole that defines the body's inertial frame), its
// path around the Sun (for the Sun's direction and distance at a date) and its default
// environment (Bond albedo and planet IR model). Every constant and its source is in
// docs/orbits.md, "Central bodies".
#include "orbits/sun.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace radnet::orbits {

/// What the planet emits in the infrared, per unit of its surface, W/m².
struct PlanetIr {
  enum class Kind {
    Uniform,  ///< the same flux everywhere (the Earth's OLR, Venus's and Jupiter's emission)
    DayNight  ///< a surface in radiative balance with the Sun: T = T_ss cos^¼ z, never below T_night
  } kind = Kind::Uniform;
  double uniform_w_m2 = 237.0;           ///< Uniform: emitted flux, W/m²
  double subsolar_temperature_k = 0.0;   ///< DayNight: T_ss under the reference solar flux, K
  double reference_flux_w_m2 = 1361.0;   ///< DayNight: the solar flux at which T_ss holds, W/m²
  double night_temperature_k = 0.0;      ///< DayNight: the floor (night side, terminator), K

  /// Emitted flux at a surface point of solar zenith angle z under the solar flux S (W/m²):
  /// Uniform: the constant; DayNight: max(σ T_ss⁴ (S / S_ref) cos z, σ T_night⁴), i.e.
  /// T = max(T_ss' cos^¼ z, T_night) with T_ss' the subsolar temperature at flux S
  /// (T⁴ ∝ S for a surface in balance).
  double exitance(double cos_zenith, double solar_flux_w_m2) const;
  /// The largest emitted flux anywhere on the body under solar flux S, W/m² (the scale of
  /// the IR load's error target).
  double maxExitance(double solar_flux_w_m2) const { return exitance(1.0, solar_flux_w_m2); }
  bool uniform() const { return kind == Kind::Uniform; }
  /// "uniform 237 W/m^2" or "day-night: T_ss 390 K at 1361 W/m^2, night 95 K".
  std::string describe() const;
};

/// Mean Keplerian elements of a heliocentric orbit and their rates (mean ecliptic and
/// equinox of J2000; Standish, "Keplerian Elements for Approximate Positions of the Major
/// Planets", JPL, Table 1, valid 1800–2050).
struct HeliocentricElements {
  double a_au, a_rate;          ///< semi-major axis, au and au per century
  double e, e_rate;             ///< eccentricity and per century
  double i_deg, i_rate;         ///< inclination, deg and deg per century
  double l_deg, l_rate;         ///< mean longitude
  double perihelion_deg, perihelion_rate;  ///< longitude of perihelion ϖ
  double node_deg, node_rate;   ///< longitude of the ascending node Ω
};

struct CentralBody {
  std::string name;            ///< "earth", "moon", "mars", "venus", "mercury", "jupiter"
  double gm_m3_s2 = 0.0;       ///< gravitational parameter μ, m³/s²
  double equatorial_radius_m = 0.0;
  double flattening = 0.0;     ///< –
  double j2 = 0.0;             ///< unnormalised zonal J2 at the equatorial radius, –
  double rotation_rad_s = 0.0; ///< sidereal rotation rate (negative: retrograde), rad/s
  double pole_ra_deg = 0.0, pole_dec_deg = 90.0;  ///< north pole in ICRF (IAU WGCCRE); the Earth's frame is its equator of date
  HeliocentricElements heliocentric{};           ///< of the body, or of the Earth–Moon barycentre for the Moon
  double bond_albedo = 0.30;   ///< –
  PlanetIr ir;                 ///< default planet IR model
  double lowest_altitude_m = 100e3;  ///< below this an altitude is taken for a unit slip (atmosphere, terrain)
  double highest_altitude_m = 3.844e8;  ///< beyond this the body no longer holds the orbit (its Hill sphere), m

  bool isEarth() const { return name == "earth"; }
  /// The Sun's mean motion about the body (rad/s): what a sun-synchronous node must drift at.
  double sunMeanMotion() const;

  /// The Earth of WGS84 (GeographicLib's GM, a, f, ω and the J2 of its normal gravity).
  static const CentralBody& earth();
  /// A body by its name (lower case); nullptr when there is none of that name.
  static const CentralBody* named(const std::string& name);
  /// The names `named` knows, in a fixed order.
  static const std::vector<std::string>& names();
};

/// The Sun seen from the body's centre at a Julian date: its direction in the body's
/// inertial frame (the Earth: the mean equator and equinox of date, sun.hpp; other bodies:
/// their IAU equator, x along the node of that equator on the ICRF equator) and distance.
SunPosition sunFromBody(const CentralBody& body, double jd);

/// Heliocentric position (m) of a body's centre in the ICRF (J2000 equatorial) frame, from
/// its mean elements; the Moon's adds its geocentric position (Astronomical Almanac, low
/// precision, 0.3°) to the Earth–Moon barycentre.
Eigen::Vector3d heliocentricPosition(const CentralBody& body, double jd);

}  // namespace radnet::orbits
