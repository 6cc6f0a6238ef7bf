// Orbits, the Sun, eclipses and attitudes against closed forms and almanac values.
#include "orbits/attitude.hpp"
#include "orbits/eclipse.hpp"
#include "orbits/orbit.hpp"
#include "orbits/sun.hpp"
#include "orbits/sweep.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace radnet::orbits;
using Catch::Matchers::Contains;

namespace {
constexpr double kDeg = M_PI / 180.0;
const double kEpoch = julianDateFromIso("2026-03-20T00:00:00Z");
}  // namespace

TEST_CASE("time: ISO 8601 UTC to Julian date and back") {
  CHECK(julianDateFromIso("2000-01-01T12:00:00Z") == Approx(2451545.0).margin(1e-9));
  CHECK(julianDateFromIso("2026-03-20") == Approx(2461119.5).margin(1e-9));
  CHECK(isoFromJulianDate(julianDateFromIso("2026-06-21T08:24:00Z")) == "2026-06-21T08:24:00Z");
  CHECK_THROWS_WITH(julianDateFromIso("21/06/2026"), Contains("ISO 8601"));
  CHECK_THROWS_WITH(julianDateFromIso("2026-13-01T00:00:00Z"), Contains("out of range"));
  CHECK_THROWS_AS(julianDateFromIso("2026-06-21T08:24:00+02:00"), std::invalid_argument);
}

TEST_CASE("Earth constants come from GeographicLib's WGS84") {
  const CentralBody& e = CentralBody::earth();
  CHECK(e.gm_m3_s2 == 3986004.418e8);
  CHECK(e.equatorial_radius_m == 6378137.0);
  CHECK(e.j2 == Approx(1.08263e-3).epsilon(1e-5));
}

TEST_CASE("Sun declination at the 2026 equinoxes and solstices within 0.01° of the almanac") {
  // Instants (UTC) from the almanac; declination 0 at the equinoxes and ± the obliquity
  // of 2026 (23.436°, IAU 2006 mean obliquity, nutation within the 0.01° allowed) at the solstices.
  CHECK(std::abs(sunDeclinationDeg(julianDateFromIso("2026-03-20T14:46:00Z"))) < 0.01);
  CHECK(sunDeclinationDeg(julianDateFromIso("2026-06-21T08:24:00Z")) == Approx(23.436).margin(0.01));
  CHECK(std::abs(sunDeclinationDeg(julianDateFromIso("2026-09-23T00:05:00Z"))) < 0.01);
  CHECK(sunDeclinationDeg(julianDateFromIso("2026-12-21T20:50:00Z")) == Approx(-23.436).margin(0.01));
  // Distance: perihelion in early January 0.9833 AU, aphelion in early July 1.0167 AU.
  CHECK(sunPosition(julianDateFromIso("2026-01-03T00:00:00Z")).distance_m / kAstronomicalUnit ==
        Approx(0.9833).margin(2e-4));
  CHECK(sunPosition(julianDateFromIso("2026-07-06T00:00:00Z")).distance_m / kAstronomicalUnit ==
        Approx(1.0167).margin(2e-4));
  CHECK(solarFlux(1361.0, kAstronomicalUnit) == 1361.0);
  CHECK(solarFlux(1361.0, 0.5 * kAstronomicalUnit) == Approx(4 * 1361.0));
}

TEST_CASE("Kepler's equation to 1e-14 for e up to 0.99, e >= 1 rejected") {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (double e : {0.0, 0.1, 0.5, 0.9, 0.99}) {
    for (int k = 0; k < 200; ++k) {
      const double m = u(rng);
      const double ecc = solveKepler(m, e);
      CHECK(std::abs(std::remainder(ecc - e * std::sin(ecc) - m, 2 * M_PI)) < 1e-13);
    }
  }
  CHECK_THROWS_AS(solveKepler(1.0, 1.0), OrbitError);
}

TEST_CASE("two-body states: vis-viva, closed orbit after one period, angular momentum along the normal") {
  CentralBody no_j2 = CentralBody::earth();
  no_j2.j2 = 0.0;
  const Orbit orbit(perigeeApogeeElements(400e3, 20000e3, 28.5, 30.0, 45.0, 10.0, no_j2), kEpoch, no_j2);
  const double a = orbit.elements().semi_major_axis_m;
  for (double t : {0.0, 1000.0, 5000.0, 20000.0}) {
    const OrbitState s = orbit.state(t);
    const double vis_viva = no_j2.gm_m3_s2 * (2 / s.position_eci_m.norm() - 1 / a);
    CHECK(s.velocity_eci_m_s.squaredNorm() == Approx(vis_viva).epsilon(1e-12));
    CHECK(s.position_eci_m.cross(s.velocity_eci_m_s).normalized().dot(orbit.normal(t)) == Approx(1.0).epsilon(1e-12));
  }
  const OrbitState s0 = orbit.state(0.0), s1 = orbit.state(orbit.period());
  CHECK((s1.position_eci_m - s0.position_eci_m).norm() < 1e-6 * a);
  // At the epoch the radius is the conic's at the given true anomaly: r = p / (1 + e cos ν₀).
  const double e = orbit.elements().eccentricity, nu0 = orbit.elements().true_anomaly_rad;
  CHECK(s0.position_eci_m.norm() == Approx(a * (1 - e * e) / (1 + e * std::cos(nu0))).epsilon(1e-12));
}

namespace {
// Argument of latitude (rad): the angle from the (drifting) ascending node to the position,
// in the orbit plane at time t.
double argumentOfLatitude(const Orbit& orbit, double t) {
  const Eigen::Vector3d r = orbit.state(t).position_eci_m, h = orbit.normal(t);
  const Eigen::Vector3d node = Eigen::Vector3d::UnitZ().cross(h).normalized();
  return std::atan2(r.dot(h.cross(node)), r.dot(node));
}
}  // namespace

TEST_CASE("the swept orbit closes: after one nodal period the argument of latitude repeats, after Kepler's it does not") {
  for (double inc : {28.5, 51.6, 97.4}) {
    const Orbit orbit(circularElements(400e3, inc, 30.0, 20.0), kEpoch);
    const double u0 = argumentOfLatitude(orbit, 0.0);
    // The nodal period closes the orbit to round-off (1e-9 rad ≈ 7 mm at 400 km).
    CHECK(std::abs(std::remainder(argumentOfLatitude(orbit, orbit.nodalPeriod()) - u0, 2 * M_PI)) < 1e-9);
    // Kepler's 2π√(a³/GM) misses by the J2 drift of ω + M: 0.1–1° here (the bug this fixes).
    CHECK(std::abs(std::remainder(argumentOfLatitude(orbit, orbit.period()) - u0, 2 * M_PI)) > 1e-3);
    // The sweep spans it: the first position of a second orbit is where the first began.
    SweepOptions opt;
    opt.positions_per_orbit = 8;
    opt.orbits = 2;
    opt.insert_eclipse_events = false;
    const auto sweep = sweepOrbit(orbit, AttitudeSpec{}, opt);
    CHECK(sweep[8].t_s == Approx(orbit.nodalPeriod()).epsilon(1e-12));
  }
}

TEST_CASE("sun-synchronous orbit: the node drifts 0.9856°/day within 1 %, and the local time holds") {
  for (double h : {500e3, 800e3}) {
    const double inc = sunSynchronousInclinationDeg(h);
    CHECK(inc > 97.0);
    CHECK(inc < 99.0);
    const Orbit orbit(circularElements(h, inc, raanForLocalTimeDeg(10.5, kEpoch)), kEpoch);
    const double deg_per_day = orbit.raanRate() * 86400.0 / kDeg;
    CHECK(deg_per_day == Approx(0.9856).epsilon(0.01));
    // After 60 days the node is still at 10:30 local time (the Sun moved as much, ±0.5°
    // from the equation of time's change in the Sun's right ascension rate).
    const double t = 60 * 86400.0;
    const Eigen::Vector3d s = sunPosition(kEpoch + 60).direction_eci;
    const double ra_sun = std::atan2(s.y(), s.x()) / kDeg;
    const double raan = (orbit.elements().raan_rad + orbit.raanRate() * t) / kDeg;
    const double local_hours = std::remainder(raan - ra_sun, 360.0) / 15.0 + 12.0;
    CHECK(local_hours == Approx(10.5).margin(0.2));
  }
  CHECK_THROWS_AS(sunSynchronousInclinationDeg(7000e3), OrbitError);
}

TEST_CASE("beta angle matches its formula from RAAN, inclination and the Sun's ecliptic longitude") {
  for (double inc : {28.5, 51.6, 98.0}) {
    for (double raan : {0.0, 40.0, 200.0}) {
      const Orbit orbit(circularElements(400e3, inc, raan), kEpoch);
      for (double t : {0.0, 86400.0 * 45}) {
        const SunPosition s = sunPosition(kEpoch + t / 86400.0);
        const double g = s.ecliptic_longitude_rad, eps = s.obliquity_rad;
        const double om = orbit.elements().raan_rad + orbit.raanRate() * t, i = inc * kDeg;
        const double formula = std::asin(std::cos(g) * std::sin(om) * std::sin(i) -
                                         std::sin(g) * std::cos(eps) * std::cos(om) * std::sin(i) +
                                         std::sin(g) * std::sin(eps) * std::cos(i));
        CHECK(betaAngle(orbit, t) == Approx(formula).margin(1e-12));
      }
    }
  }
  // An orbit defined by its beta has that beta at the epoch.
  for (double beta : {-60.0, 0.0, 35.0, 80.0})
    CHECK(betaAngle(Orbit(betaElements(500e3, beta, kEpoch), kEpoch), 0.0) / kDeg == Approx(beta).margin(1e-9));
}

TEST_CASE("eclipse fraction of circular orbits: (1/π) acos(√(h² + 2Rh) / ((R + h) cos β)) within 0.1 % of the period") {
  // The formula is for a two-body orbit: with J2 the argument of latitude advances 0.4 %
  // faster than 2π/T at 400 km (Ṁ + ω̇ = n(1 + 3k) in the equatorial plane), which would
  // shorten the eclipse by 0.16 % of T. So the test uses WGS84 without J2.
  CentralBody two_body = CentralBody::earth();
  two_body.j2 = 0.0;
  const double R = two_body.equatorial_radius_m;
  for (double h : {400e3, 800e3, 2000e3}) {
    const double critical = std::asin(R / (R + h)) / kDeg;
    for (double beta : {0.0, 30.0, 60.0, critical - 2.0, critical + 2.0}) {
      const Orbit orbit(betaElements(h, beta, kEpoch, two_body), kEpoch, two_body);
      const double T = orbit.period();
      // Start at orbit noon (away from the shadow) by sweeping from the epoch over 1.5 orbits.
      const auto events = eclipseEvents(orbit, 0.0, 1.5 * T);
      const double x = std::sqrt(h * h + 2 * R * h) / ((R + h) * std::cos(beta * kDeg));
      const double expected = x < 1 ? std::acos(x) / M_PI : 0.0;
      INFO("h = " << h / 1e3 << " km, β = " << beta << "°, critical " << critical << "°");
      if (expected == 0.0) {
        CHECK(events.empty());
        continue;
      }
      // The cylindrical shadow edge lies midway through the penumbra: take the middle of
      // the penumbra and umbra crossings at entry and at exit.
      double entry = -1, exit = -1;
      for (size_t k = 0; k + 1 < events.size(); ++k) {
        if (events[k].kind == EclipseEvent::PenumbraEntry && events[k + 1].kind == EclipseEvent::UmbraEntry &&
            entry < 0)
          entry = 0.5 * (events[k].t_s + events[k + 1].t_s);
        if (events[k].kind == EclipseEvent::UmbraExit && events[k + 1].kind == EclipseEvent::PenumbraExit &&
            entry >= 0 && exit < 0)
          exit = 0.5 * (events[k].t_s + events[k + 1].t_s);
      }
      REQUIRE(entry >= 0);
      REQUIRE(exit > entry);
      CHECK(std::abs((exit - entry) / T - expected) < 1e-3);
      // The sunlit fraction is 0 inside and 1 outside, with the penumbra between.
      CHECK(sunlitFraction(orbit.state(0.5 * (entry + exit)).position_eci_m, sunEci(orbit, 0.5 * (entry + exit)), R) ==
            0.0);
      const double mid_pen = events.front().t_s + 1.0;
      const double f = sunlitFraction(orbit.state(mid_pen).position_eci_m, sunEci(orbit, mid_pen), R);
      CHECK(f > 0.0);
      CHECK(f < 1.0);
    }
  }
}

TEST_CASE("attitudes: nadir frame, Sun pointing, inertial, spin, and a two-axis pointing") {
  const Orbit orbit(circularElements(500e3, 51.6, 30.0), kEpoch);
  const double t = 1234.0;
  const OrbitState st = orbit.state(t);
  const Eigen::Vector3d sun = sunPosition(kEpoch + t / 86400).direction_eci;
  AttitudeSpec nadir;
  const Eigen::Matrix3d r = bodyFromEci(nadir, orbit, st, sun, t);
  CHECK((r * r.transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-12);
  CHECK(r.determinant() == Approx(1.0));
  CHECK((r * (-st.position_eci_m.normalized()) - Eigen::Vector3d::UnitZ()).norm() < 1e-12);  // +z to the Earth
  CHECK((r * st.velocity_eci_m_s.normalized()).x() > 0.999);                                 // +x along velocity
  CHECK((r * orbit.normal(t) + Eigen::Vector3d::UnitY()).norm() < 1e-6);                     // +y = −orbit normal

  AttitudeSpec sunpt;
  sunpt.mode = AttitudeSpec::Mode::Sun;
  CHECK((bodyFromEci(sunpt, orbit, st, sun, t) * sun - Eigen::Vector3d::UnitZ()).norm() < 1e-12);

  AttitudeSpec inertial;
  inertial.mode = AttitudeSpec::Mode::Inertial;
  inertial.body_from_eci = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  CHECK((bodyFromEci(inertial, orbit, st, sun, 0) - bodyFromEci(inertial, orbit, st, sun, 5000)).norm() == 0.0);

  AttitudeSpec spin = inertial;
  spin.mode = AttitudeSpec::Mode::Spin;
  spin.spin_rate_deg_s = 6.0;  // one turn per minute
  const Eigen::Matrix3d r0 = bodyFromEci(spin, orbit, st, sun, 0), r60 = bodyFromEci(spin, orbit, st, sun, 60);
  CHECK((r0 - r60).norm() < 1e-12);
  CHECK((r0 - bodyFromEci(spin, orbit, st, sun, 15)).norm() > 0.5);

  AttitudeSpec point;
  point.mode = AttitudeSpec::Mode::Pointing;
  point.pointing.primary_body = Eigen::Vector3d::UnitX();
  point.pointing.primary = Target::Sun;
  point.pointing.secondary_body = Eigen::Vector3d::UnitZ();
  point.pointing.secondary = Target::Nadir;
  const Eigen::Matrix3d rp = bodyFromEci(point, orbit, st, sun, t);
  CHECK((rp * sun - Eigen::Vector3d::UnitX()).norm() < 1e-12);
  CHECK((rp * (-st.position_eci_m.normalized())).z() > 0.0);
  CHECK(earthFixedInBody(nadir));
  CHECK_FALSE(earthFixedInBody(sunpt));
}

TEST_CASE("sweep: evenly spaced positions plus exact eclipse events, sunlit fraction 0 in eclipse") {
  const Orbit orbit(betaElements(400e3, 10.0, kEpoch), kEpoch);
  SweepOptions opt;
  opt.positions_per_orbit = 36;
  const auto sweep = sweepOrbit(orbit, AttitudeSpec{}, opt);
  int events = 0, dark = 0;
  for (size_t k = 0; k < sweep.size(); ++k) {
    events += sweep[k].event;
    dark += sweep[k].sunlit_fraction == 0.0;
    if (k) CHECK(sweep[k].t_s > sweep[k - 1].t_s);
    CHECK(sweep[k].sun_body.norm() == Approx(1.0));
    CHECK(sweep[k].planet_body.z() == Approx(1.0));  // nadir: the Earth along +z
    CHECK(sweep[k].solar_flux_w_m2 ==
          Approx(1361.0 * std::pow(kAstronomicalUnit / (sunPosition(kEpoch).distance_m), 2)).epsilon(2e-3));
  }
  CHECK(events == 4);  // penumbra and umbra, in and out
  CHECK(dark > 0);
  CHECK(sweep.size() == 36 + 4);
}

TEST_CASE("sweep by true anomaly: equal steps of argument of latitude ω(t) + ν on an eccentric orbit, time increasing") {
  const Orbit orbit(perigeeApogeeElements(500e3, 8000e3, 63.4, 0, 270, 0), kEpoch);
  SweepOptions opt;
  opt.positions_per_orbit = 12;
  opt.orbits = 2;
  opt.insert_eclipse_events = false;
  opt.spacing = SweepOptions::Spacing::TrueAnomaly;
  AttitudeSpec inertial;
  inertial.mode = AttitudeSpec::Mode::Inertial;
  const auto sweep = sweepOrbit(orbit, inertial, opt);
  REQUIRE(sweep.size() == 24);
  const double e = orbit.elements().eccentricity;
  for (size_t k = 0; k < sweep.size(); ++k) {
    if (k) CHECK(sweep[k].t_s > sweep[k - 1].t_s);
    // True anomaly from the position: the angle from perigee in the orbit plane.
    const OrbitState st = orbit.state(sweep[k].t_s);
    const double r = st.position_eci_m.norm(), p = orbit.elements().semi_major_axis_m * (1 - e * e);
    const double cos_nu = (p / r - 1) / e;
    // Equal steps of ω + ν: ν falls behind 2πk/12 by the perigee's J2 drift ω̇ t.
    CHECK(cos_nu == Approx(std::cos(2 * M_PI * (k % 12) / 12.0 - orbit.argPerigeeRate() * sweep[k].t_s)).margin(1e-9));
  }
}

TEST_CASE("bad orbits are rejected with clear errors") {
  CHECK_THROWS_WITH(circularElements(-10e3, 51.6, 0), Contains("altitude"));
  CHECK_THROWS_WITH(circularElements(std::nan(""), 51.6, 0), Contains("altitude"));
  KeplerElements hyper = circularElements(500e3, 0, 0);
  hyper.eccentricity = 1.2;
  CHECK_THROWS_WITH(Orbit(hyper, kEpoch), Contains("eccentricity") && Contains("e < 1"));
  KeplerElements low = circularElements(500e3, 0, 0);
  low.eccentricity = 0.5;  // perigee inside the Earth
  CHECK_THROWS_WITH(Orbit(low, kEpoch), Contains("inside the Earth"));
  KeplerElements nan = circularElements(500e3, 0, 0);
  nan.raan_rad = std::nan("");
  CHECK_THROWS_WITH(Orbit(nan, kEpoch), Contains("RAAN"));
  CHECK_THROWS_AS(perigeeApogeeElements(500e3, 400e3, 0, 0, 0, 0), OrbitError);
  CHECK_THROWS_AS(betaElements(500e3, 120.0, kEpoch), OrbitError);
}

TEST_CASE("osculating elements from a state: Vallado's Example 2-5, and the propagator's own elements") {
  // Vallado, Fundamentals of Astrodynamics (4th ed.), Example 2-5: r, v in km and km/s.
  const double mu_km = 398600.4418;
  const OrbitState s{{6524.834e3, 6862.875e3, 6448.296e3}, {4.901327e3, 5.533756e3, -1.976341e3}};
  const KeplerElements el = elementsFromState(s, mu_km * 1e9);
  const double deg = M_PI / 180;
  // The book prints 5 to 6 digits: a = 36 127.343 km, e = 0.832 853, i = 87.870°, Ω = 227.89°,
  // ω = 53.38°, ν = 92.335°; tolerances are half a unit of the last printed digit, a whole
  // one for Ω, which the book truncates (227.898° printed 227.89°).
  CHECK(el.semi_major_axis_m / 1e3 == Approx(36127.343).margin(5e-3));
  CHECK(el.eccentricity == Approx(0.832853).margin(5e-7));
  CHECK(el.inclination_rad / deg == Approx(87.870).margin(5e-4));
  CHECK(el.raan_rad / deg == Approx(227.89).margin(1e-2));
  CHECK(el.arg_perigee_rad / deg == Approx(53.38).margin(5e-3));
  CHECK(el.true_anomaly_rad / deg == Approx(92.335).margin(5e-4));

  // The propagator's elements at t are the osculating elements of its state for μ = n̄² a³,
  // at any t (Ω and ω have drifted), to round-off.
  KeplerElements start;
  start.semi_major_axis_m = 7.4e6;
  start.eccentricity = 0.07;
  start.inclination_rad = 63.4 * deg;
  start.raan_rad = 40 * deg;
  start.arg_perigee_rad = 270 * deg;
  start.true_anomaly_rad = 10 * deg;
  const Orbit orbit(start, 2461000.5);
  const double mu = std::pow(orbit.meanMotion(), 2) * std::pow(start.semi_major_axis_m, 3);
  for (double t : {0.0, 1234.5, 86400.0 * 3.3}) {
    INFO("t = " << t << " s");
    const KeplerElements model = orbit.elementsAt(t), back = elementsFromState(orbit.state(t), mu);
    CHECK(back.semi_major_axis_m == Approx(model.semi_major_axis_m).epsilon(1e-10));
    CHECK(back.eccentricity == Approx(model.eccentricity).margin(1e-10));
    CHECK(back.inclination_rad == Approx(model.inclination_rad).margin(1e-10));
    CHECK(back.raan_rad == Approx(model.raan_rad).margin(1e-9));
    CHECK(back.arg_perigee_rad == Approx(model.arg_perigee_rad).margin(1e-8));
    CHECK(back.true_anomaly_rad == Approx(model.true_anomaly_rad).margin(1e-8));
  }
  CHECK_THROWS_AS(elementsFromState({{7e6, 0, 0}, {0, 2e4, 0}}, mu), OrbitError);  // hyperbolic
}
