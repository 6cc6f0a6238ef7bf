#include "orbits/planet_sky.hpp"

#include "solver/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace radnet::orbits {

namespace {

constexpr int kGaussOrder = 12;

// Gauss–Legendre nodes and weights on [−1, 1] (Newton's iteration on P_N from the
// Chebyshev guesses; Golub & Welsch give the same to round-off).
struct GaussRule {
  std::array<double, kGaussOrder> x{}, w{};
};

const GaussRule& gaussRule() {
  static const GaussRule rule = [] {
    GaussRule r;
    const int n = kGaussOrder;
    for (int i = 0; i < n; ++i) {
      double x = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = x;
        for (int k = 2; k <= n; ++k) {
          const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
          p0 = p1, p1 = p2;
        }
        dp = n * (x * p1 - p0) / (x * x - 1.0);
        const double step = p1 / dp;
        x -= step;
        if (std::abs(step) < 1e-16) break;
      }
      r.x[static_cast<size_t>(i)] = x;
      r.w[static_cast<size_t>(i)] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
    return r;
  }();
  return rule;
}

// a + b cos(φ − phase), b ≥ 0, along one ring.
struct Wave {
  double a = 1.0, b = 0.0, phase = 0.0;
};

// Half-width of the arc about `phase` where the wave is positive: π (everywhere), < 0 (nowhere).
double positiveHalfWidth(const Wave& w) {
  if (w.b <= std::abs(w.a)) return w.a > 0 ? M_PI : -1.0;
  return std::acos(std::clamp(-w.a / w.b, -1.0, 1.0));
}

// ∫ f g dφ over [x0, x1]: (A + B cos(φ−p))(a + b cos(φ−q)) expanded, cos cos = ½ cos(p−q) + ½ cos(2φ−p−q).
double productIntegral(const Wave& f, const Wave& g, double x0, double x1) {
  const auto antiderivative = [&](double x) {
    return f.a * g.a * x + f.a * g.b * std::sin(x - g.phase) + g.a * f.b * std::sin(x - f.phase) +
           0.5 * f.b * g.b * (std::cos(f.phase - g.phase) * x + 0.5 * std::sin(2.0 * x - f.phase - g.phase));
  };
  return antiderivative(x1) - antiderivative(x0);
}

// ∫ max(0, f) max(0, g) dφ around the ring: f's positive arc against g's and its copies 2π apart.
double ringIntegral(const Wave& f, const Wave& g) {
  const double hf = positiveHalfWidth(f), hg = positiveHalfWidth(g);
  if (hf < 0 || hg < 0) return 0.0;
  const double gc = f.phase + std::remainder(g.phase - f.phase, 2.0 * M_PI);
  double sum = 0.0;
  for (const double shift : {-2.0 * M_PI, 0.0, 2.0 * M_PI}) {
    const double lo = std::max(f.phase - hf, gc + shift - hg), hi = std::min(f.phase + hf, gc + shift + hg);
    if (hi > lo) sum += productIntegral(f, g, lo, hi);
  }
  return sum;
}

// c·v and the phase and length of v's part normal to c in the ring frame (e1, e2).
Wave ringWave(const Eigen::Vector3d& v, const Eigen::Vector3d& c, const Eigen::Vector3d& e1,
              const Eigen::Vector3d& e2, double along_scale, double across_scale) {
  const double x = v.dot(e1), y = v.dot(e2);
  return {along_scale * v.dot(c), across_scale * std::hypot(x, y), std::atan2(y, x)};
}

// The day-night emission as floor + K max(0, cos z − c0) (W/m²); uniform: floor only.
struct Emission {
  double floor = 0.0, k = 0.0, c0 = 0.0;
};

Emission emissionParts(const PlanetIr& ir, double flux) {
  if (ir.uniform()) return {ir.uniform_w_m2, 0.0, 0.0};
  const double floor = ir.exitance(-1.0, flux), k = ir.exitance(1.0, flux);
  if (k <= floor) return {floor, 0.0, 0.0};
  return {floor, k, floor / k};
}

// γ (angle at the planet's centre from the sub-spacecraft point) of a line of sight at θ
// from the centre's direction: the near intersection, by the sine rule.
double gammaOfTheta(double theta, double d, double r) { return std::asin(std::min(1.0, d * std::sin(theta) / r)) - theta; }

}  // namespace

PlanetChannels planetRadiance(const PlanetView& v, const Eigen::Vector3d& dir) {
  const Eigen::Vector3d& c = v.toward_center;
  const double cos_t = dir.dot(c), cos_max = std::sqrt(std::max(0.0, 1.0 - v.capSin2()));
  if (cos_t < cos_max) return {};
  const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
  const double gamma = gammaOfTheta(std::atan2(sin_t, cos_t), v.distance_m, v.radius_m);
  const Eigen::Vector3d across = sin_t > 1e-300 ? Eigen::Vector3d((dir - cos_t * c) / sin_t) : c.unitOrthogonal();
  const Eigen::Vector3d surface_normal = -std::cos(gamma) * c + std::sin(gamma) * across;
  const double cos_z = surface_normal.dot(v.toward_sun);
  return {1.0 / M_PI, v.albedo * v.solar_flux_w_m2 * std::max(0.0, cos_z) / M_PI,
          v.ir.exitance(cos_z, v.solar_flux_w_m2) / M_PI};
}

double planeToSphereViewFactor(double distance_over_radius, double beta) {
  const double h = std::max(distance_over_radius, 1.0 + 1e-12);  // an orbit lies above its planet
  const double edge = std::acos(1.0 / h);  // beyond this tilt the plane cuts the sphere
  if (beta <= edge) return std::cos(beta) / (h * h);
  if (beta >= M_PI - edge) return 0.0;
  const double x = std::sqrt(h * h - 1.0), y = -x / std::tan(beta);
  return 0.5 - std::asin(std::min(1.0, x / (h * std::sin(beta)))) / M_PI +
         (std::cos(beta) * std::acos(std::clamp(y, -1.0, 1.0)) -
          x * std::sqrt(std::max(0.0, 1.0 - h * h * std::cos(beta) * std::cos(beta)))) /
             (M_PI * h * h);
}

PlanetChannels unobstructedPlanetLoads(const PlanetView& v, const Eigen::Vector3d& normal) {
  const Eigen::Vector3d& c = v.toward_center;
  const double d = v.distance_m, r = v.radius_m, gamma_max = std::acos(std::min(1.0, r / d));
  const Emission em = emissionParts(v.ir, v.solar_flux_w_m2);
  PlanetChannels sum;
  sum.view = planeToSphereViewFactor(d / r, std::acos(std::clamp(normal.dot(c), -1.0, 1.0)));
  sum.ir = em.floor * sum.view;
  // The rest lives where the Sun is up (albedo) or warms the ground past the floor: rings.
  const double psi = std::acos(std::clamp(-v.toward_sun.dot(c), -1.0, 1.0));
  const bool lit = v.albedo > 0 && v.solar_flux_w_m2 > 0 && psi - gamma_max < M_PI / 2;
  const bool warm = em.k > 0 && psi - gamma_max < std::acos(em.c0);
  if (sum.view <= 0 || (!lit && !warm)) return sum;
  const Eigen::Vector3d e1 = c.unitOrthogonal(), e2 = c.cross(e1);
  // Where the rings' arcs change: the plane's horizon, the terminator (and the night floor).
  std::vector<double> cuts{0.0, gamma_max};
  const Wave n_full = ringWave(normal, c, e1, e2, 1.0, 1.0), sun_full = ringWave(v.toward_sun, c, e1, e2, 1.0, 1.0);
  const double theta_max = std::asin(std::sqrt(v.capSin2())), theta_horizon = std::atan2(std::abs(n_full.a), n_full.b);
  if (theta_horizon < theta_max) cuts.push_back(gammaOfTheta(theta_horizon, d, r));
  for (const double c0 : {0.0, em.c0})
    for (const double g : {std::acos(c0) - psi, psi - std::acos(c0), psi + std::acos(c0)})
      if (g > 0 && g < gamma_max) cuts.push_back(g);
  std::sort(cuts.begin(), cuts.end());
  const GaussRule& rule = gaussRule();
  for (size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double g0 = cuts[k], g1 = cuts[k + 1];
    if (!(g1 > g0)) continue;
    for (int q = 0; q < kGaussOrder; ++q) {
      const double gamma = 0.5 * (g0 + g1) + 0.5 * (g1 - g0) * rule.x[static_cast<size_t>(q)];
      const double weight = 0.5 * (g1 - g0) * rule.w[static_cast<size_t>(q)];
      // dω = sin θ (dθ/dγ) dγ dφ, θ = atan2(R sin γ, d − R cos γ).
      const double theta = std::atan2(r * std::sin(gamma), d - r * std::cos(gamma));
      const double dtheta = (r * d * std::cos(gamma) - r * r) / (d * d - 2.0 * d * r * std::cos(gamma) + r * r);
      const double sin_theta = std::sin(theta), cos_theta = std::cos(theta);
      const double jacobian = weight * sin_theta * dtheta / M_PI;
      // The waves' phases are the same on every ring: only their two parts scale.
      const Wave plane{n_full.a * cos_theta, n_full.b * sin_theta, n_full.phase};
      const Wave sun{-sun_full.a * std::cos(gamma), sun_full.b * std::sin(gamma), sun_full.phase};
      if (lit) sum.albedo += jacobian * v.albedo * v.solar_flux_w_m2 * ringIntegral(plane, sun);
      if (warm) sum.ir += jacobian * em.k * ringIntegral(plane, Wave{sun.a - em.c0, sun.b, sun.phase});
    }
  }
  return sum;
}

}  // namespace radnet::orbits
