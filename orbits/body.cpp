#include "orbits/body.hpp"

#include "solver/units.hpp"

#include "orbits/earth.hpp"
#include "orbits/orbit.hpp"

#include <algorithm>

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/NormalGravity.hpp>

#include <cmath>
#include <sstream>

namespace radnet::orbits {
namespace {

constexpr double kDay = kSecondsPerDay;
constexpr double kSunGm = 1.32712440018e20;        // m³/s² (IAU 2009 / DE430)
constexpr double kObliquityJ2000Deg = 23.43928;    // mean obliquity of the ecliptic at J2000 (IAU 1976/2006)
constexpr double kEarthMoonMassRatio = 81.30056;   // M_E / M_M (DE430)

double degPerDayToRadPerS(double deg_per_day) { return units::degToRad(deg_per_day) / kDay; }

// The Hill radius a (m / 3M)^(1/3) of a body of parameter μ on an orbit of a (m) about a
// primary of parameter μ_p: beyond it the primary, not the body, holds a spacecraft.
double hillRadius(double a_m, double mu, double mu_primary) { return a_m * std::cbrt(mu / (3.0 * mu_primary)); }

// The Sun's flux at a body's mean distance (au), W/m², at 1361 W/m² at 1 au.
double meanFlux(double a_au) { return 1361.0 / (a_au * a_au); }

PlanetIr uniformIr(double w_m2) {
  PlanetIr ir;
  ir.kind = PlanetIr::Kind::Uniform;
  ir.uniform_w_m2 = w_m2;
  return ir;
}

PlanetIr dayNightIr(double subsolar_k, double reference_flux, double night_k) {
  PlanetIr ir;
  ir.kind = PlanetIr::Kind::DayNight;
  ir.subsolar_temperature_k = subsolar_k;
  ir.reference_flux_w_m2 = reference_flux;
  ir.night_temperature_k = night_k;
  return ir;
}

// Standish, Table 1 (1800–2050): a, ȧ; e, ė; I, İ; L, L̇; ϖ, ϖ̇; Ω, Ω̇ per Julian century.
constexpr HeliocentricElements kMercuryOrbit{0.38709927, 0.00000037, 0.20563593, 0.00001906, 7.00497902, -0.00594749,
                                             252.25032350, 149472.67411175, 77.45779628, 0.16047689, 48.33076593,
                                             -0.12534081};
constexpr HeliocentricElements kVenusOrbit{0.72333566, 0.00000390, 0.00677672, -0.00004107, 3.39467605, -0.00078890,
                                           181.97909950, 58517.81538729, 131.60246718, 0.00268329, 76.67984255,
                                           -0.27769418};
constexpr HeliocentricElements kEarthMoonOrbit{1.00000261, 0.00000562, 0.01671123, -0.00004392, -0.00001531,
                                               -0.01294668, 100.46457166, 35999.37244981, 102.93768193, 0.32327364,
                                               0.0, 0.0};
constexpr HeliocentricElements kMarsOrbit{1.52371034, 0.00001847, 0.09339410, 0.00007882, 1.84969142, -0.00813131,
                                          -4.55343205, 19140.30268499, -23.94362959, 0.44441088, 49.55953891,
                                          -0.29257343};
constexpr HeliocentricElements kJupiterOrbit{5.20288700, -0.00011607, 0.04838624, -0.00013253, 1.30439695,
                                             -0.00183714, 34.39644051, 3034.74612775, 14.72847983, 0.21252668,
                                             100.47390909, 0.20469106};

CentralBody makeEarth() {
  const GeographicLib::NormalGravity& g = GeographicLib::NormalGravity::WGS84();
  CentralBody b;
  b.name = "earth";
  b.gm_m3_s2 = GeographicLib::Constants::WGS84_GM();
  b.equatorial_radius_m = GeographicLib::Constants::WGS84_a();
  b.flattening = GeographicLib::Constants::WGS84_f();
  b.j2 = g.DynamicalFormFactor(2);
  b.rotation_rad_s = GeographicLib::Constants::WGS84_omega();
  b.heliocentric = kEarthMoonOrbit;
  b.bond_albedo = 0.30;     // Gilmore, Spacecraft Thermal Control Handbook, ch. 2 (orbit average)
  b.ir = uniformIr(237.0);  // OLR, global mean (Gilmore, ch. 2)
  b.lowest_altitude_m = 100e3;
  b.highest_altitude_m = 3.844e8;  // the Moon's mean distance
  return b;
}

CentralBody makeMoon() {
  CentralBody b;
  b.name = "moon";
  b.gm_m3_s2 = 4.9028000661e12;  // DE430 (Folkner et al. 2014)
  b.equatorial_radius_m = 1737.4e3;  // IAU mean radius (Archinal et al. 2018)
  b.j2 = 2.0321e-4;                 // GRAIL GL0660B, −C20 unnormalised (Konopliv et al. 2013)
  b.rotation_rad_s = degPerDayToRadPerS(13.17635815);  // IAU W rate (synchronous)
  b.pole_ra_deg = 269.9949, b.pole_dec_deg = 66.5392;  // IAU mean pole (periodic terms of ≤ 4° left out)
  b.heliocentric = kEarthMoonOrbit;
  b.bond_albedo = 0.11;  // NASA Moon fact sheet (Williams)
  // Diviner: equatorial noon ≈ 390 K, pre-dawn ≈ 95 K (Williams et al. 2017, Icarus 283).
  b.ir = dayNightIr(390.0, meanFlux(1.0), 95.0);
  b.lowest_altitude_m = 10e3;  // low lunar orbits fly at 20–50 km (LRO's was 50 km)
  b.highest_altitude_m = hillRadius(3.844e8, b.gm_m3_s2, GeographicLib::Constants::WGS84_GM());
  return b;
}

CentralBody makeMars() {
  CentralBody b;
  b.name = "mars";
  b.gm_m3_s2 = 4.282837362e13;      // DE430
  b.equatorial_radius_m = 3396.19e3;  // IAU (Archinal et al. 2018)
  b.flattening = (3396.19 - 3376.20) / 3396.19;
  b.j2 = 1.96045e-3;                // GMM-2B (Lemoine et al. 2001)
  b.rotation_rad_s = degPerDayToRadPerS(350.891982443297);
  b.pole_ra_deg = 317.68143, b.pole_dec_deg = 52.88650;  // IAU 2009 (Archinal et al. 2011)
  b.heliocentric = kMarsOrbit;
  b.bond_albedo = 0.25;  // NASA Mars fact sheet
  // Radiative balance at the mean distance, ((1 − A) S / (0.95 σ))^¼ ≈ 300 K; equatorial
  // pre-dawn ≈ 180 K (Viking IRTM, Kieffer et al. 1977).
  b.ir = dayNightIr(300.0, meanFlux(kMarsOrbit.a_au), 180.0);
  b.lowest_altitude_m = 100e3;  // aerobraking altitudes; below, the atmosphere
  b.highest_altitude_m = hillRadius(kMarsOrbit.a_au * kAstronomicalUnit, b.gm_m3_s2, kSunGm);
  return b;
}

CentralBody makeVenus() {
  CentralBody b;
  b.name = "venus";
  b.gm_m3_s2 = 3.24858592e14;  // DE430
  b.equatorial_radius_m = 6051.8e3;
  b.j2 = 4.458e-6;  // Konopliv et al. 1999
  b.rotation_rad_s = degPerDayToRadPerS(-1.4813688);  // retrograde
  b.pole_ra_deg = 272.76, b.pole_dec_deg = 67.16;
  b.heliocentric = kVenusOrbit;
  b.bond_albedo = 0.76;  // Moroz 1985; Haus et al. 2016
  // Emission balancing what it absorbs, (1 − A) S / 4 at its mean distance ≈ 156 W/m².
  b.ir = uniformIr((1.0 - 0.76) * meanFlux(kVenusOrbit.a_au) / 4.0);
  b.lowest_altitude_m = 150e3;  // the upper atmosphere
  b.highest_altitude_m = hillRadius(kVenusOrbit.a_au * kAstronomicalUnit, b.gm_m3_s2, kSunGm);
  return b;
}

CentralBody makeMercury() {
  CentralBody b;
  b.name = "mercury";
  b.gm_m3_s2 = 2.2031868551e13;  // DE430
  b.equatorial_radius_m = 2440.53e3;
  b.j2 = 5.031e-5;  // MESSENGER (Smith et al. 2012)
  b.rotation_rad_s = degPerDayToRadPerS(6.1385108);
  b.pole_ra_deg = 281.0103, b.pole_dec_deg = 61.4155;
  b.heliocentric = kMercuryOrbit;
  b.bond_albedo = 0.088;  // Mallama et al. 2002
  // Radiative balance at the mean distance ≈ 625 K (≈ 700 K at perihelion); night ≈ 100 K
  // (Vasavada et al. 1999, Icarus 141).
  b.ir = dayNightIr(625.0, meanFlux(kMercuryOrbit.a_au), 100.0);
  b.lowest_altitude_m = 10e3;
  b.highest_altitude_m = hillRadius(kMercuryOrbit.a_au * kAstronomicalUnit, b.gm_m3_s2, kSunGm);
  return b;
}

CentralBody makeJupiter() {
  CentralBody b;
  b.name = "jupiter";
  b.gm_m3_s2 = 1.26686534e17;  // the planet alone (JUP230)
  b.equatorial_radius_m = 71492e3;
  b.flattening = (71492.0 - 66854.0) / 71492.0;
  b.j2 = 1.46965e-2;  // Juno (Iess et al. 2018), at 71,492 km
  b.rotation_rad_s = degPerDayToRadPerS(870.536);  // System III
  b.pole_ra_deg = 268.056595, b.pole_dec_deg = 64.495303;
  b.heliocentric = kJupiterOrbit;
  b.bond_albedo = 0.503;         // Cassini (Li et al. 2018, Nature Communications 9)
  b.ir = uniformIr(14.10);       // emitted power, same source
  b.lowest_altitude_m = 1000e3;  // the atmosphere (Juno's perijove: ~4,000 km)
  b.highest_altitude_m = hillRadius(kJupiterOrbit.a_au * kAstronomicalUnit, b.gm_m3_s2, kSunGm);
  return b;
}

const std::vector<CentralBody>& bodies() {
  static const std::vector<CentralBody> all = {makeEarth(), makeMoon(),    makeMars(),
                                               makeVenus(), makeMercury(), makeJupiter()};
  return all;
}

// Heliocentric position (au) in the J2000 ecliptic from Standish's mean elements.
Eigen::Vector3d eclipticPositionAu(const HeliocentricElements& h, double jd) {
  const double T = (jd - kJ2000) / 36525.0, deg = units::kRadPerDeg;
  const double a = h.a_au + h.a_rate * T, e = h.e + h.e_rate * T, inc = (h.i_deg + h.i_rate * T) * deg;
  const double l = h.l_deg + h.l_rate * T, peri = h.perihelion_deg + h.perihelion_rate * T;
  const double node = (h.node_deg + h.node_rate * T) * deg, argp = peri * deg - node;
  const double ecc = solveKepler((l - peri) * deg, e);
  const Eigen::Vector3d in_plane(a * (std::cos(ecc) - e), a * std::sqrt(1 - e * e) * std::sin(ecc), 0.0);
  return (Eigen::AngleAxisd(node, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(inc, Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(argp, Eigen::Vector3d::UnitZ())) *
         in_plane;
}

// The Moon's geocentric position (m) in the ecliptic of date (Astronomical Almanac, "Moon,
// low precision": 0.3° in longitude, 0.2° in latitude, 0.003 Earth radii in distance).
Eigen::Vector3d moonGeocentricEcliptic(double jd) {
  const double T = (jd - kJ2000) / 36525.0, deg = units::kRadPerDeg;
  const auto s = [&](double a0, double rate) { return std::sin((a0 + rate * T) * deg); };
  const auto c = [&](double a0, double rate) { return std::cos((a0 + rate * T) * deg); };
  const double lambda = 218.32 + 481267.881 * T + 6.29 * s(135.0, 477198.87) - 1.27 * s(259.3, -413335.36) +
                        0.66 * s(235.7, 890534.22) + 0.21 * s(269.9, 954397.74) - 0.19 * s(357.5, 35999.05) -
                        0.11 * s(186.5, 966404.03);
  const double beta = 5.13 * s(93.3, 483202.02) + 0.28 * s(228.2, 960400.89) - 0.28 * s(318.3, 6003.15) -
                      0.17 * s(217.6, -407332.21);
  const double parallax = 0.9508 + 0.0518 * c(135.0, 477198.87) + 0.0095 * c(259.3, -413335.36) +
                          0.0078 * c(235.7, 890534.22) + 0.0028 * c(269.9, 954397.74);
  const double r = CentralBody::earth().equatorial_radius_m / std::sin(parallax * deg);
  return r * Eigen::Vector3d(std::cos(beta * deg) * std::cos(lambda * deg), std::cos(beta * deg) * std::sin(lambda * deg),
                             std::sin(beta * deg));
}

// ICRF → the body's inertial frame: z the IAU pole, x along ẑ_ICRF × pole (the ascending
// node of the body's equator on the ICRF equator).
Eigen::Matrix3d bodyFromIcrf(const CentralBody& b) {
  const double ra = units::degToRad(b.pole_ra_deg), dec = units::degToRad(b.pole_dec_deg);
  const Eigen::Vector3d z(std::cos(dec) * std::cos(ra), std::cos(dec) * std::sin(ra), std::sin(dec));
  const Eigen::Vector3d x = Eigen::Vector3d::UnitZ().cross(z).normalized();
  Eigen::Matrix3d m;
  m.row(0) = x.transpose();
  m.row(1) = z.cross(x).transpose();
  m.row(2) = z.transpose();
  return m;
}

const Eigen::Matrix3d& icrfFromEcliptic() {
  static const Eigen::Matrix3d m =
      Eigen::AngleAxisd(units::degToRad(kObliquityJ2000Deg), Eigen::Vector3d::UnitX()).toRotationMatrix();
  return m;
}

}  // namespace

double PlanetIr::exitance(double cos_zenith, double solar_flux) const {
  if (kind == Kind::Uniform) return uniform_w_m2;
  const double night = units::kStefanBoltzmann * std::pow(night_temperature_k, 4);
  const double day = units::kStefanBoltzmann * std::pow(subsolar_temperature_k, 4) * (solar_flux / reference_flux_w_m2) *
                     std::max(0.0, cos_zenith);
  return std::max(day, night);
}

std::string PlanetIr::describe() const {
  std::ostringstream s;
  if (kind == Kind::Uniform)
    s << "uniform " << uniform_w_m2 << " W/m^2";
  else
    s << "day-night: T = max(T_ss cos^(1/4) z, T_night), T_ss " << subsolar_temperature_k << " K at "
      << reference_flux_w_m2 << " W/m^2 (T_ss^4 follows the solar flux), T_night " << night_temperature_k << " K";
  return s.str();
}

double CentralBody::sunMeanMotion() const {
  // The mean longitude's rate is deg per Julian century.
  return units::degToRad(heliocentric.l_rate) / (36525.0 * kDay);
}

const CentralBody& CentralBody::earth() { return bodies().front(); }

const CentralBody* CentralBody::named(const std::string& name) {
  for (const CentralBody& b : bodies())
    if (b.name == name) return &b;
  return nullptr;
}

const std::vector<std::string>& CentralBody::names() {
  static const std::vector<std::string> all = [] {
    std::vector<std::string> n;
    for (const CentralBody& b : bodies()) n.push_back(b.name);
    return n;
  }();
  return all;
}

Eigen::Vector3d heliocentricPosition(const CentralBody& body, double jd) {
  Eigen::Vector3d ecliptic = eclipticPositionAu(body.heliocentric, jd) * kAstronomicalUnit;
  if (body.name == "moon") ecliptic += moonGeocentricEcliptic(jd) * (kEarthMoonMassRatio / (kEarthMoonMassRatio + 1.0));
  else if (body.isEarth()) ecliptic -= moonGeocentricEcliptic(jd) / (kEarthMoonMassRatio + 1.0);
  return icrfFromEcliptic() * ecliptic;
}

SunPosition sunFromBody(const CentralBody& body, double jd) {
  if (body.isEarth()) return sunPosition(jd);
  const Eigen::Vector3d to_sun_icrf = -heliocentricPosition(body, jd);
  const Eigen::Matrix3d frame = bodyFromIcrf(body);
  SunPosition s;
  s.distance_m = to_sun_icrf.norm();
  s.direction_eci = frame * (to_sun_icrf / s.distance_m);
  const Eigen::Vector3d ecliptic = icrfFromEcliptic().transpose() * to_sun_icrf;
  s.ecliptic_longitude_rad = std::atan2(ecliptic.y(), ecliptic.x());
  // The body's obliquity: its pole against the ecliptic pole.
  const Eigen::Vector3d ecliptic_pole = icrfFromEcliptic() * Eigen::Vector3d::UnitZ();
  s.obliquity_rad = std::acos(std::clamp(frame.row(2).dot(ecliptic_pole), -1.0, 1.0));
  return s;
}

}  // namespace radnet::orbits
