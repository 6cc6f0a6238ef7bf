#include "orbits/eclipse.hpp"

#include "orbits/body.hpp"
#include "orbits/earth.hpp"
#include "orbits/sun.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::orbits {
namespace {

struct DiscGeometry {
  double a, b, c;  // apparent radii of Sun and Earth, their separation (rad)
};

DiscGeometry discs(const Eigen::Vector3d& sat, const Eigen::Vector3d& sun, double re) {
  const Eigen::Vector3d to_sun = sun - sat, to_earth = -sat;
  DiscGeometry g;
  g.a = std::asin(std::min(1.0, kSunRadius / to_sun.norm()));
  g.b = std::asin(std::min(1.0, re / to_earth.norm()));
  g.c = std::acos(std::clamp(to_sun.normalized().dot(to_earth.normalized()), -1.0, 1.0));
  return g;
}

}  // namespace

Eigen::Vector3d sunEci(const Orbit& orbit, double t) {
  const SunPosition s = sunFromBody(orbit.body(), orbit.epochJd() + t / kSecondsPerDay);
  return s.direction_eci * s.distance_m;
}

double sunlitFraction(const Eigen::Vector3d& sat, const Eigen::Vector3d& sun, double re) {
  const DiscGeometry g = discs(sat, sun, re);
  if (g.c >= g.a + g.b) return 1.0;                              // no overlap
  if (g.c <= g.b - g.a) return 0.0;                              // umbra: the Earth covers the Sun
  if (g.c <= g.a - g.b) return 1.0 - (g.b * g.b) / (g.a * g.a);  // annular (never in Earth orbit)
  // Partial overlap of two discs (planar approximation, radii ≪ 1 rad for the Sun).
  const double a2 = g.a * g.a, b2 = g.b * g.b, c = g.c;
  const double x = (c * c + a2 - b2) / (2 * c);
  const double y = std::sqrt(std::max(0.0, a2 - x * x));
  const double overlap =
      a2 * std::acos(std::clamp(x / g.a, -1.0, 1.0)) + b2 * std::acos(std::clamp((c - x) / g.b, -1.0, 1.0)) - c * y;
  return std::clamp(1.0 - overlap / (M_PI * a2), 0.0, 1.0);
}

std::vector<EclipseEvent> eclipseEvents(const Orbit& orbit, double t0, double t1) {
  const double re = orbit.body().equatorial_radius_m;
  // Penumbra boundary: c = a + b; umbra boundary: c = b − a.
  auto pen = [&](double t) {
    const DiscGeometry g = discs(orbit.state(t).position_eci_m, sunEci(orbit, t), re);
    return g.c - (g.a + g.b);
  };
  auto umb = [&](double t) {
    const DiscGeometry g = discs(orbit.state(t).position_eci_m, sunEci(orbit, t), re);
    return g.c - (g.b - g.a);
  };
  std::vector<EclipseEvent> events;
  const double step = orbit.period() / 720.0;
  auto scan = [&](auto&& f, EclipseEvent::Kind entry, EclipseEvent::Kind exit) {
    double ta = t0, fa = f(ta);
    while (ta < t1) {
      const double tb = std::min(t1, ta + step), fb = f(tb);
      if ((fa > 0) != (fb > 0)) {
        double lo = ta, hi = tb, flo = fa;
        while (hi - lo > 1e-3) {
          const double mid = 0.5 * (lo + hi), fm = f(mid);
          if ((fm > 0) == (flo > 0)) {
            lo = mid;
            flo = fm;
          } else {
            hi = mid;
          }
        }
        events.push_back({fa > 0 ? entry : exit, 0.5 * (lo + hi)});
      }
      ta = tb;
      fa = fb;
    }
  };
  scan(pen, EclipseEvent::PenumbraEntry, EclipseEvent::PenumbraExit);
  scan(umb, EclipseEvent::UmbraEntry, EclipseEvent::UmbraExit);
  std::sort(events.begin(), events.end(), [](const EclipseEvent& x, const EclipseEvent& y) { return x.t_s < y.t_s; });
  return events;
}

}  // namespace radnet::orbits
