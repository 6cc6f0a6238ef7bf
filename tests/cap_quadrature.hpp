#pragma once
// What a nadir-facing plate at distance r from the centre of a sphere of radius R receives
// from a Lambertian sphere whose exitance depends only on ψ, the angle at the centre from
// the sub-plate point (axisymmetric): E = ∫ (M(ψ)/π) cos θ_plate cos θ_ground / d² · 2π R²
// sin ψ dψ over the visible cap, by the midpoint rule (200,000 steps: 1e-9 relative).
#include <cmath>

namespace radnet::testing {

template <class Exitance>
double nadirPlateIrradiance(double R, double r, Exitance exitance_w_m2) {
  const int steps = 200000;
  const double psi_max = std::acos(R / r);
  double sum = 0.0;
  for (int k = 0; k < steps; ++k) {
    const double psi = (k + 0.5) * psi_max / steps;
    const double d2 = R * R + r * r - 2 * R * r * std::cos(psi), d = std::sqrt(d2);
    const double cos_plate = (r - R * std::cos(psi)) / d, cos_ground = (r * std::cos(psi) - R) / d;
    sum += exitance_w_m2(psi) / M_PI * cos_plate * cos_ground / d2 * 2 * M_PI * R * R * std::sin(psi);
  }
  return sum * psi_max / steps;
}

}  // namespace radnet::testing
