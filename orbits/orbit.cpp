#include "orbits/orbit.hpp"

#include "solver/units.hpp"

#include "orbits/sun.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace radnet::orbits {
namespace {

constexpr double kTropicalYearDays = 365.2421897;

void requireFinite(double x, const char* what) {
  if (!std::isfinite(x)) throw OrbitError(std::string(what) + " is not finite");
}

}  // namespace

double solveKepler(double m, double e) {
  if (!(e >= 0 && e < 1)) throw OrbitError("Kepler's equation needs 0 <= e < 1");
  m = std::remainder(m, 2 * M_PI);  // [−π, π]
  double ecc = m + 0.85 * e * (std::sin(m) >= 0 ? 1.0 : -1.0);
  for (int k = 0; k < 50; ++k) {
    const double f = ecc - e * std::sin(ecc) - m;
    const double fp = 1 - e * std::cos(ecc);
    const double step = f / fp;
    ecc -= step;
    if (std::abs(step) < 1e-15) break;
  }
  return ecc;
}

Orbit::Orbit(const KeplerElements& el, double epoch_jd, const CentralBody& body)
    : el_(el), epoch_jd_(epoch_jd), body_(body) {
  requireFinite(el.semi_major_axis_m, "semi-major axis");
  requireFinite(el.eccentricity, "eccentricity");
  requireFinite(el.inclination_rad, "inclination");
  requireFinite(el.raan_rad, "RAAN");
  requireFinite(el.arg_perigee_rad, "argument of perigee");
  requireFinite(el.true_anomaly_rad, "true anomaly");
  requireFinite(epoch_jd, "epoch");
  if (el.eccentricity < 0 || el.eccentricity >= 1) {
    std::ostringstream s;
    s << "eccentricity " << el.eccentricity << " is not an ellipse; expected 0 <= e < 1 (hyperbolic and parabolic "
      << "trajectories are not orbits to sweep)";
    throw OrbitError(s.str());
  }
  if (el.inclination_rad < 0 || el.inclination_rad > M_PI) throw OrbitError("inclination must be in [0, 180] deg");
  const double perigee = el.semi_major_axis_m * (1 - el.eccentricity);
  if (!(perigee > body.equatorial_radius_m)) {
    std::ostringstream s;
    s << "perigee radius " << perigee << " m is inside " << (body.isEarth() ? std::string("the Earth") : body.name) << " (equatorial radius "
      << body.equatorial_radius_m << " m); altitudes must be > 0";
    throw OrbitError(s.str());
  }
  const double a = el.semi_major_axis_m, e = el.eccentricity;
  const double n0 = std::sqrt(body.gm_m3_s2 / (a * a * a));
  const double p = a * (1 - e * e);
  const double k = 1.5 * body.j2 * std::pow(body.equatorial_radius_m / p, 2);
  const double ci = std::cos(el.inclination_rad);
  // Secular J2 rates (Vallado, eqs. 9-41 to 9-43).
  raan_rate_ = -k * n0 * ci;
  argp_rate_ = 0.5 * k * n0 * (5 * ci * ci - 1);
  mean_motion_ = n0 * (1 + 0.5 * k * std::sqrt(1 - e * e) * (3 * ci * ci - 1));
  // Mean anomaly at the epoch from the true anomaly.
  const double ecc0 = 2 * std::atan2(std::sqrt(1 - e) * std::sin(el.true_anomaly_rad / 2),
                                     std::sqrt(1 + e) * std::cos(el.true_anomaly_rad / 2));
  m0_ = ecc0 - e * std::sin(ecc0);
}

double Orbit::period() const {
  const double a = el_.semi_major_axis_m;
  return 2 * M_PI * std::sqrt(a * a * a / body_.gm_m3_s2);
}

OrbitState Orbit::state(double t) const {
  const double a = el_.semi_major_axis_m, e = el_.eccentricity;
  const double raan = el_.raan_rad + raan_rate_ * t, argp = el_.arg_perigee_rad + argp_rate_ * t;
  const double ecc = solveKepler(m0_ + mean_motion_ * t, e);
  const double cosE = std::cos(ecc), sinE = std::sin(ecc);
  const double sq = std::sqrt(1 - e * e);
  // Perifocal position and velocity (the velocity of the osculating ellipse).
  const Eigen::Vector3d pos_pf(a * (cosE - e), a * sq * sinE, 0.0);
  const double edot = mean_motion_ / (1 - e * cosE);
  const Eigen::Vector3d vel_pf(-a * sinE * edot, a * sq * cosE * edot, 0.0);
  const Eigen::Matrix3d eciFromPerifocal = (Eigen::AngleAxisd(raan, Eigen::Vector3d::UnitZ()) *
                                            Eigen::AngleAxisd(el_.inclination_rad, Eigen::Vector3d::UnitX()) *
                                            Eigen::AngleAxisd(argp, Eigen::Vector3d::UnitZ()))
                                               .toRotationMatrix();
  return {eciFromPerifocal * pos_pf, eciFromPerifocal * vel_pf};
}

KeplerElements Orbit::elementsAt(double t) const {
  KeplerElements el = el_;
  const double e = el_.eccentricity;
  const double ecc = solveKepler(m0_ + mean_motion_ * t, e);
  const auto wrap = [](double angle) {
    const double w = std::fmod(angle, 2 * M_PI);
    return w < 0 ? w + 2 * M_PI : w;
  };
  el.raan_rad = wrap(el_.raan_rad + raan_rate_ * t);
  el.arg_perigee_rad = wrap(el_.arg_perigee_rad + argp_rate_ * t);
  el.true_anomaly_rad =
      wrap(2 * std::atan2(std::sqrt(1 + e) * std::sin(ecc / 2), std::sqrt(1 - e) * std::cos(ecc / 2)));
  return el;
}

KeplerElements elementsFromState(const OrbitState& s, double mu) {
  const Eigen::Vector3d& r = s.position_eci_m;
  const Eigen::Vector3d& v = s.velocity_eci_m_s;
  const Eigen::Vector3d h = r.cross(v), node = Eigen::Vector3d::UnitZ().cross(h);
  const Eigen::Vector3d e_vec = ((v.squaredNorm() - mu / r.norm()) * r - r.dot(v) * v) / mu;
  const double energy = v.squaredNorm() / 2 - mu / r.norm();
  if (!(energy < 0) || !(h.norm() > 0)) throw OrbitError("the state is not a bound orbit");
  const auto angle = [](const Eigen::Vector3d& from, const Eigen::Vector3d& to, bool flip) {
    const double c = std::clamp(from.normalized().dot(to.normalized()), -1.0, 1.0);
    return flip ? 2 * M_PI - std::acos(c) : std::acos(c);
  };
  KeplerElements el;
  el.semi_major_axis_m = -mu / (2 * energy);
  el.eccentricity = e_vec.norm();
  el.inclination_rad = std::acos(std::clamp(h.z() / h.norm(), -1.0, 1.0));
  constexpr double kTiny = 1e-11;
  const bool equatorial = node.norm() < kTiny * h.norm(), circular = el.eccentricity < kTiny;
  el.raan_rad = equatorial ? 0.0 : angle(Eigen::Vector3d::UnitX(), node, node.y() < 0);
  const Eigen::Vector3d reference = equatorial ? Eigen::Vector3d::UnitX() : node;  // where ω (or u) starts
  if (!circular) {
    // An equatorial orbit measures ω from x, in the direction of motion.
    const bool flip = equatorial ? (h.z() >= 0 ? e_vec.y() < 0 : e_vec.y() > 0) : e_vec.z() < 0;
    el.arg_perigee_rad = angle(reference, e_vec, flip);
    el.true_anomaly_rad = angle(e_vec, r, r.dot(v) < 0);
  } else {
    const bool flip = equatorial ? (h.z() >= 0 ? r.y() < 0 : r.y() > 0) : r.z() < 0;
    el.true_anomaly_rad = angle(reference, r, flip);  // argument of latitude (or true longitude)
  }
  return el;
}

double Orbit::nodalPeriod() const { return 2 * M_PI / (mean_motion_ + argp_rate_); }

double Orbit::timeOfTrueAnomaly(double nu, int turns) const {
  const double e = el_.eccentricity;
  const double ecc = 2 * std::atan2(std::sqrt(1 - e) * std::sin(nu / 2), std::sqrt(1 + e) * std::cos(nu / 2));
  double dm = (ecc - e * std::sin(ecc)) - m0_;
  dm = std::fmod(dm, 2 * M_PI);
  if (dm < 0) dm += 2 * M_PI;
  return (dm + 2 * M_PI * turns) / mean_motion_;
}

Eigen::Vector3d Orbit::normal(double t) const {
  const double raan = el_.raan_rad + raan_rate_ * t, i = el_.inclination_rad;
  return Eigen::Vector3d(std::sin(i) * std::sin(raan), -std::sin(i) * std::cos(raan), std::cos(i));
}

KeplerElements circularElements(double altitude_m, double inclination_deg, double raan_deg, double arg_latitude_deg,
                                const CentralBody& body) {
  if (!(std::isfinite(altitude_m) && altitude_m > 0)) {
    std::ostringstream s;
    s << "altitude " << altitude_m << " m: expected a finite value > 0";
    throw OrbitError(s.str());
  }
  KeplerElements el;
  el.semi_major_axis_m = body.equatorial_radius_m + altitude_m;
  el.inclination_rad = units::degToRad(inclination_deg);
  el.raan_rad = units::degToRad(raan_deg);
  el.true_anomaly_rad = units::degToRad(arg_latitude_deg);
  return el;
}

KeplerElements perigeeApogeeElements(double hp, double ha, double inclination_deg, double raan_deg,
                                     double arg_perigee_deg, double true_anomaly_deg, const CentralBody& body) {
  if (!(std::isfinite(hp) && hp > 0 && std::isfinite(ha) && ha >= hp))
    throw OrbitError("perigee and apogee altitudes must be finite with 0 < perigee <= apogee");
  const double rp = body.equatorial_radius_m + hp, ra = body.equatorial_radius_m + ha;
  KeplerElements el;
  el.semi_major_axis_m = 0.5 * (rp + ra);
  el.eccentricity = (ra - rp) / (ra + rp);
  el.inclination_rad = units::degToRad(inclination_deg);
  el.raan_rad = units::degToRad(raan_deg);
  el.arg_perigee_rad = units::degToRad(arg_perigee_deg);
  el.true_anomaly_rad = units::degToRad(true_anomaly_deg);
  return el;
}

double sunSynchronousInclinationDeg(double altitude_m, const CentralBody& body) {
  const double a = body.equatorial_radius_m + altitude_m;
  // The node follows the mean Sun: once per tropical year about the Earth, once per the
  // body's year elsewhere (the Moon's year is the Earth's).
  const double rate = body.isEarth() ? 2 * M_PI / (kTropicalYearDays * kSecondsPerDay) : body.sunMeanMotion();
  const double c = -2.0 * rate * std::pow(a, 3.5) /
                   (3.0 * body.j2 * body.equatorial_radius_m * body.equatorial_radius_m * std::sqrt(body.gm_m3_s2));
  if (!(c >= -1)) {
    std::ostringstream msg;
    msg << "no sun-synchronous orbit exists about " << body.name << " at " << altitude_m
        << " m: its J2 cannot turn the node once per " << (body.isEarth() ? "year" : "year of its own")
        << (body.isEarth() ? " above ~5970 km" : "");
    throw OrbitError(msg.str());
  }
  return units::radToDeg(std::acos(c));
}

double raanForLocalTimeDeg(double ltan_hours, double epoch_jd, const CentralBody& body) {
  if (!(std::isfinite(ltan_hours) && ltan_hours >= 0 && ltan_hours < 24))
    throw OrbitError("local time of the ascending node must be in [0, 24) hours");
  // The Sun's right ascension is local noon: RAAN = α_sun + (LTAN − 12 h) × 15°/h.
  const SunPosition s = sunFromBody(body, epoch_jd);
  const double ra_sun = units::radToDeg(std::atan2(s.direction_eci.y(), s.direction_eci.x()));
  return std::fmod(ra_sun + (ltan_hours - 12.0) * 15.0 + 720.0, 360.0);
}

KeplerElements betaElements(double altitude_m, double beta_deg, double epoch_jd, const CentralBody& body) {
  if (!(std::isfinite(beta_deg) && beta_deg >= -90 && beta_deg <= 90))
    throw OrbitError("beta must be in [-90, 90] deg");
  const Eigen::Vector3d s = sunFromBody(body, epoch_jd).direction_eci;
  // Orbit normal h = sin β s + cos β p, p ⟂ s in the plane of s and the pole, so that
  // asin(h·s) = β; with β = 0 the Sun lies in the orbit plane.
  Eigen::Vector3d p = Eigen::Vector3d::UnitZ() - s.z() * s;
  p.normalize();
  const double b = units::degToRad(beta_deg);
  Eigen::Vector3d h = std::sin(b) * s + std::cos(b) * p;
  const double inc = std::acos(std::clamp(h.z(), -1.0, 1.0));
  const double raan = std::atan2(h.x(), -h.y());
  KeplerElements el = circularElements(altitude_m, units::radToDeg(inc), units::radToDeg(raan), 0.0, body);
  return el;
}

double betaAngle(const Orbit& orbit, double t) {
  const Eigen::Vector3d s = sunFromBody(orbit.body(), orbit.epochJd() + t / kSecondsPerDay).direction_eci;
  return std::asin(std::clamp(orbit.normal(t).dot(s), -1.0, 1.0));
}

}  // namespace radnet::orbits
