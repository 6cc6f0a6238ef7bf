#include "orbits/sweep.hpp"

#include "orbits/body.hpp"
#include "orbits/earth.hpp"
#include "orbits/sun.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::orbits {
namespace {

// Seconds after the epoch at which the true anomaly has advanced by dnu (rad, ≥ 0) from
// the epoch's, counting whole revolutions.
double timeOfAdvance(const Orbit& orbit, double dnu) {
  const int turns = static_cast<int>(std::floor(dnu / (2 * M_PI)));
  const double rest = dnu - 2 * M_PI * turns, revolution = 2 * M_PI / orbit.meanMotion();
  double t = orbit.timeOfTrueAnomaly(orbit.elements().true_anomaly_rad + rest, turns);
  // Just past a whole turn, round-off can put the mean anomaly a hair behind the epoch's, and
  // the wrap then counts one revolution too many.
  if (rest < M_PI && t - turns * revolution > 0.5 * revolution) t -= revolution;
  return t;
}

}  // namespace

std::vector<SweepPosition> sweepOrbit(const Orbit& orbit, const AttitudeSpec& attitude, const SweepOptions& opt) {
  if (opt.positions_per_orbit < 1 || opt.positions_per_orbit > 100000)
    throw OrbitError("positions per orbit must be in [1, 100000]");
  if (!(std::isfinite(opt.orbits) && opt.orbits > 0 && opt.orbits <= 10000))
    throw OrbitError("number of orbits must be in (0, 10000]");
  // The nodal period, so that the swept orbit closes with the propagation's J2 drift.
  const double period = orbit.nodalPeriod(), span = opt.orbits * period;
  const int regular = static_cast<int>(std::ceil(opt.positions_per_orbit * opt.orbits - 1e-9));
  std::vector<std::pair<double, bool>> times;
  for (int k = 0; k < regular; ++k) {
    if (opt.spacing == SweepOptions::Spacing::Time) {
      times.emplace_back(k * period / opt.positions_per_orbit, false);
    } else {  // equal steps of argument of latitude ω(t) + ν from the epoch's
      // Solve ν(t) − ν₀ + ω̇ t = Δu by fixed point: it contracts by ω̇/n ≈ 1e-3 per iteration.
      const double du = 2 * M_PI * k / opt.positions_per_orbit;
      double t = timeOfAdvance(orbit, du);
      for (int it = 0; it < 4; ++it) t = timeOfAdvance(orbit, du - orbit.argPerigeeRate() * t);
      times.emplace_back(t, false);
    }
  }
  if (opt.insert_eclipse_events)
    for (const EclipseEvent& e : eclipseEvents(orbit, 0.0, span)) times.emplace_back(e.t_s, true);
  std::sort(times.begin(), times.end());
  std::vector<SweepPosition> out;
  const double re = orbit.body().equatorial_radius_m;
  for (const auto& [t, event] : times) {
    SweepPosition p;
    p.t_s = t;
    p.event = event;
    const OrbitState st = orbit.state(t);
    const SunPosition sun = sunFromBody(orbit.body(), orbit.epochJd() + t / kSecondsPerDay);
    const Eigen::Vector3d sun_pos = sun.direction_eci * sun.distance_m;
    const Eigen::Vector3d to_sun = (sun_pos - st.position_eci_m).normalized();
    try {
      p.body_from_eci = bodyFromEci(attitude, orbit, st, to_sun, t);
    } catch (const OrbitError& e) {  // say when: a pointing's targets may align at one instant only
      throw OrbitError(std::string(e.what()) + " at t = " + std::to_string(t) + " s of the orbit");
    }
    p.position_eci_m = st.position_eci_m;
    p.velocity_eci_m_s = st.velocity_eci_m_s;
    p.elements = orbit.elementsAt(t);
    p.sun_body = p.body_from_eci * to_sun;
    p.planet_body = p.body_from_eci * (-st.position_eci_m.normalized());
    p.planet_distance_m = st.position_eci_m.norm();
    p.sunlit_fraction = sunlitFraction(st.position_eci_m, sun_pos, re);
    p.beta_rad = betaAngle(orbit, t);
    p.solar_flux_w_m2 = solarFlux(opt.solar_constant_w_m2, (sun_pos - st.position_eci_m).norm());
    out.push_back(p);
  }
  return out;
}

}  // namespace radnet::orbits
