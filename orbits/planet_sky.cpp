#include "orbits/planet_sky.hpp"

#include "solver/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>

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
  double a = 1.0, b = 0.0;
};

using PositiveArc = PlanetRings::Arc;

// Where a wave is positive (the arc's ends then need no trigonometric call of their own).
PositiveArc positiveArc(const Wave& w) {
  if (w.b <= std::abs(w.a)) return w.a > 0 ? PositiveArc{} : PositiveArc{true};
  const double c = std::clamp(-w.a / w.b, -1.0, 1.0);
  return {false, std::acos(c), c, std::sqrt(std::max(0.0, 1.0 - c * c))};
}

// The phase of g's wave less f's, δ ∈ (−π, π], with its cosine and sine: the same on every
// ring (only the waves' two parts scale from ring to ring).
struct PhaseGap {
  double delta = 0.0, cos_delta = 1.0, sin_delta = 0.0;
};

// An angle u (from f's phase) with its cosine and sine.
struct Angle {
  double u, c, s;
};

// ∫ max(0, f) max(0, g) dφ around the ring, φ measured from f's phase (u = φ − phase_f), g's
// positive arc hg given:
// f = A + B cos u, g = a + b cos(u − δ). The product's antiderivative
//     A a u + A b sin(u − δ) + a B sin u + ½ B b (u cos δ + ½ sin(2u − δ))
// at the ends of f's positive arc hf against g's and its copies 2π apart; the ends' sines
// by the angle-addition formulas from the arcs' and the gap's cosines and sines. (hf given:
// the albedo's and the IR's integrals of one ring share the plane's arc and its acos.)
double ringIntegral(const Wave& f, const PositiveArc& hf, const Wave& g, const PositiveArc& hg, const PhaseGap& gap) {
  if (hg.none || hf.none) return 0.0;
  const double cd = gap.cos_delta, sd = gap.sin_delta;
  const auto antiderivative = [&](const Angle& x) {
    const double sin_u_minus_delta = x.s * cd - x.c * sd;
    const double sin_2u_minus_delta = 2.0 * x.s * x.c * cd - (x.c * x.c - x.s * x.s) * sd;
    return f.a * g.a * x.u + f.a * g.b * sin_u_minus_delta + g.a * f.b * x.s +
           0.5 * f.b * g.b * (cd * x.u + 0.5 * sin_2u_minus_delta);
  };
  // g's arc ends, δ ∓ half (their cosines and sines shift by 2π unchanged).
  const Angle g_lo{0.0, cd * hg.cos_half + sd * hg.sin_half, sd * hg.cos_half - cd * hg.sin_half};
  const Angle g_hi{0.0, cd * hg.cos_half - sd * hg.sin_half, sd * hg.cos_half + cd * hg.sin_half};
  double sum = 0.0;
  for (const double shift : {-2.0 * M_PI, 0.0, 2.0 * M_PI}) {
    const double glo = gap.delta + shift - hg.half, ghi = gap.delta + shift + hg.half;
    const Angle lo = -hf.half >= glo ? Angle{-hf.half, hf.cos_half, -hf.sin_half} : Angle{glo, g_lo.c, g_lo.s};
    const Angle hi = hf.half <= ghi ? Angle{hf.half, hf.cos_half, hf.sin_half} : Angle{ghi, g_hi.c, g_hi.s};
    if (hi.u > lo.u) sum += antiderivative(hi) - antiderivative(lo);
  }
  return sum;
}

// c·v and the length of v's part normal to c, and that part's direction in the ring frame
// (e1, e2) as its cosine and sine (zero part: along e1).
struct RingVector {
  Wave wave;
  double cos_phase = 1.0, sin_phase = 0.0;
};

RingVector ringVector(const Eigen::Vector3d& v, const Eigen::Vector3d& c, const Eigen::Vector3d& e1,
                      const Eigen::Vector3d& e2) {
  const double x = v.dot(e1), y = v.dot(e2), across = std::hypot(x, y);
  if (!(across > 0)) return {{v.dot(c), 0.0}, 1.0, 0.0};
  return {{v.dot(c), across}, x / across, y / across};
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
  // γ = asin(x) − θ by the sine rule, x = d sin θ / R: its cosine and sine by the
  // angle-difference formulas (asin's cosine √(1 − x²) ≥ 0), no trigonometric call.
  const double x = std::min(1.0, v.distance_m * sin_t / v.radius_m), cos_asin = std::sqrt(std::max(0.0, 1.0 - x * x));
  const double cos_gamma = cos_asin * cos_t + x * sin_t, sin_gamma = x * cos_t - cos_asin * sin_t;
  const double sun_center = v.toward_sun.dot(c);
  const double sun_across = sin_t > 1e-300 ? (v.toward_sun.dot(dir) - cos_t * sun_center) / sin_t
                                           : v.toward_sun.dot(c.unitOrthogonal());
  const double cos_z = -cos_gamma * sun_center + sin_gamma * sun_across;
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
  return PlanetRings(v).loads(normal);
}

PlanetRings::PlanetRings(const PlanetView& v) : view_(v) {
  const Eigen::Vector3d& c = v.toward_center;
  const double d = v.distance_m, r = v.radius_m;
  gamma_max_ = std::acos(std::min(1.0, r / d));
  theta_max_ = std::asin(std::sqrt(v.capSin2()));
  const Emission em = emissionParts(v.ir, v.solar_flux_w_m2);
  floor_ = em.floor, k_ = em.k, c0_ = em.c0;
  // The rest lives where the Sun is up (albedo) or warms the ground past the floor: rings.
  psi_ = std::acos(std::clamp(-v.toward_sun.dot(c), -1.0, 1.0));
  lit_ = v.albedo > 0 && v.solar_flux_w_m2 > 0 && psi_ - gamma_max_ < M_PI / 2;
  warm_ = em.k > 0 && psi_ - gamma_max_ < std::acos(em.c0);
  e1_ = c.unitOrthogonal(), e2_ = c.cross(e1_);
  const RingVector sun = ringVector(v.toward_sun, c, e1_, e2_);
  sun_a_ = sun.wave.a, sun_b_ = sun.wave.b, sun_cos_ = sun.cos_phase, sun_sin_ = sun.sin_phase;
  // Where the rings' arcs change but for a plane's horizon: the terminator (and the night floor).
  cuts_ = {0.0, gamma_max_};
  for (const double c0 : {0.0, em.c0})
    for (const double g : {std::acos(c0) - psi_, psi_ - std::acos(c0), psi_ + std::acos(c0)})
      if (g > 0 && g < gamma_max_) cuts_.push_back(g);
  std::sort(cuts_.begin(), cuts_.end());
  for (size_t k = 0; k + 1 < cuts_.size(); ++k)
    for (int q = 0; q < kGaussOrder; ++q) points_.push_back(point(cuts_[k], cuts_[k + 1], q));
}

PlanetRings::Point PlanetRings::point(double g0, double g1, int q) const {
  const GaussRule& rule = gaussRule();
  const double d = view_.distance_m, r = view_.radius_m;
  const double gamma = 0.5 * (g0 + g1) + 0.5 * (g1 - g0) * rule.x[static_cast<size_t>(q)];
  const double weight = 0.5 * (g1 - g0) * rule.w[static_cast<size_t>(q)];
  // dω = sin θ (dθ/dγ) dγ dφ, θ = atan2(R sin γ, d − R cos γ): sin θ and cos θ are the
  // two legs over the line of sight's length ρ.
  const double cos_gamma = std::cos(gamma), sin_gamma = std::sin(gamma);
  const double rho2 = d * d - 2.0 * d * r * cos_gamma + r * r, rho = std::sqrt(rho2);
  const double sin_theta = r * sin_gamma / rho, cos_theta = (d - r * cos_gamma) / rho;
  const double dtheta = (r * d * cos_gamma - r * r) / rho2;
  const Wave sun{-sun_a_ * cos_gamma, sun_b_ * sin_gamma};
  return {weight * sin_theta * dtheta / M_PI, cos_theta,          sin_theta,
          sun.a,                            sun.b,              positiveArc(sun),
          positiveArc(Wave{sun.a - c0_, sun.b})};
}

PlanetChannels PlanetRings::loads(const Eigen::Vector3d& normal) const {
  const PlanetView& v = view_;
  const Eigen::Vector3d& c = v.toward_center;
  const double d = v.distance_m, r = v.radius_m;
  PlanetChannels sum;
  sum.view = planeToSphereViewFactor(d / r, std::acos(std::clamp(normal.dot(c), -1.0, 1.0)));
  sum.ir = floor_ * sum.view;
  if (sum.view <= 0 || (!lit_ && !warm_)) return sum;
  const RingVector n_full = ringVector(normal, c, e1_, e2_);
  const double cos_gap = sun_cos_ * n_full.cos_phase + sun_sin_ * n_full.sin_phase;
  const double sin_gap = sun_sin_ * n_full.cos_phase - sun_cos_ * n_full.sin_phase;
  const PhaseGap gap{std::atan2(sin_gap, cos_gap), cos_gap, sin_gap};
  // The plane's horizon, where its arcs start to cut the rings: a cut of its own.
  const double theta_horizon = std::atan2(std::abs(n_full.wave.a), n_full.wave.b);
  const double horizon = theta_horizon < theta_max_ ? gammaOfTheta(theta_horizon, d, r) : -1.0;
  // The waves' phases are the same on every ring: only their two parts scale.
  const auto add = [&](const Point& p) {
    const Wave plane{n_full.wave.a * p.cos_theta, n_full.wave.b * p.sin_theta};
    const Wave sun{p.sun_a, p.sun_b};
    const bool albedo = lit_ && !p.sun_arc.none, ir = warm_ && !p.warm_arc.none;
    if (!albedo && !ir) return;
    const PositiveArc plane_arc = positiveArc(plane);
    if (albedo) sum.albedo += p.jacobian * v.albedo * v.solar_flux_w_m2 * ringIntegral(plane, plane_arc, sun, p.sun_arc, gap);
    if (ir) sum.ir += p.jacobian * k_ * ringIntegral(plane, plane_arc, Wave{sun.a - c0_, sun.b}, p.warm_arc, gap);
  };
  for (size_t k = 0; k + 1 < cuts_.size(); ++k) {
    const double g0 = cuts_[k], g1 = cuts_[k + 1];
    if (!(g1 > g0)) continue;
    if (horizon > g0 && horizon < g1) {
      for (const auto& [a, b] : {std::pair{g0, horizon}, std::pair{horizon, g1}})
        for (int q = 0; q < kGaussOrder; ++q) add(point(a, b, q));
      continue;
    }
    for (int q = 0; q < kGaussOrder; ++q) add(points_[k * static_cast<size_t>(kGaussOrder) + static_cast<size_t>(q)]);
  }
  return sum;
}

PlanetChannels PlanetRings::facetLoads(const std::vector<Eigen::Vector3d>& normals,
                                       const std::vector<double>& shares) const {
  const double sin_max = std::sqrt(view_.capSin2());
  Eigen::Vector3d seeing = Eigen::Vector3d::Zero();
  PlanetChannels sum;
  for (size_t k = 0; k < normals.size(); ++k) {
    const double cos_c = normals[k].dot(view_.toward_center);
    if (cos_c >= sin_max)
      seeing += shares[k] * normals[k];
    else if (cos_c > -sin_max)
      sum += loads(normals[k]) * shares[k];
  }
  const double length = seeing.norm();
  if (length > 0) sum += loads(seeing / length) * length;
  return sum;
}

}  // namespace radnet::orbits
