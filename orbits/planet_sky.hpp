#pragma once
// The central body as a far radiance field in the body frame at one position: a sphere of
// radius R whose centre lies at distance d along a unit direction, Lambertian albedo
// (radiance a S max(0, cos z) / π) and IR emission (PlanetIr's exitance / π), z the solar
// zenith angle where the line of sight meets the surface. Far field: every point of the
// spacecraft sees the planet as its reference point does (the parallax of a 10 m
// spacecraft at 400 km is 2.5e-5 rad).
//
// unobstructedPlanetLoads(n) integrates a plane's albedo and day-night emission over the
// visible cap in closed form along each ring of constant angle from the planet's centre: along a ring both the
// plane's cosine and the cosine of the solar zenith angle are a + b cos(φ − φ0), so each
// ring's integral of their positive parts' product is an elementary function; the rings
// are summed by Gauss–Legendre in the angle γ at the planet's centre (smooth up to the
// limb, where dθ/dγ = 0), split where the plane's horizon or the terminator starts to
// cut the rings.
#include "orbits/body.hpp"

#include <Eigen/Dense>

#include <vector>

namespace radnet::orbits {

struct PlanetView {
  Eigen::Vector3d toward_center = Eigen::Vector3d::UnitZ();  ///< unit, body frame
  double distance_m = 0.0;                                   ///< to the planet's centre
  double radius_m = 0.0;
  Eigen::Vector3d toward_sun = Eigen::Vector3d::UnitX();     ///< unit, body frame
  double solar_flux_w_m2 = 0.0;
  double albedo = 0.0;  ///< Bond albedo (one value: a latitude table needs the planet rays)
  PlanetIr ir;

  /// sin² of the planet's angular radius (the largest view factor any plate can have), –
  double capSin2() const { return std::min(1.0, (radius_m / distance_m) * (radius_m / distance_m)); }
};

/// Three quantities carried together: the view factor's (radiance 1/π on the disc), the
/// albedo's and the planet IR's.
struct PlanetChannels {
  double view = 0.0, albedo = 0.0, ir = 0.0;
  PlanetChannels& operator+=(const PlanetChannels& o) { return view += o.view, albedo += o.albedo, ir += o.ir, *this; }
  PlanetChannels operator*(double s) const { return {view * s, albedo * s, ir * s}; }
};

/// Radiance (per sr: 1/π, W/m²/sr, W/m²/sr) arriving from unit direction `dir`.
PlanetChannels planetRadiance(const PlanetView& view, const Eigen::Vector3d& dir);

/// The view factor from a plane element to a sphere at distance_over_radius = d/R, the
/// normal at `beta` (rad) from the line to the centre, whether the plane cuts the sphere
/// or not (Howell, A Catalog of Radiation Heat Transfer Configuration Factors, "plane
/// element to sphere").
double planeToSphereViewFactor(double distance_over_radius, double beta);

/// What an unobstructed plane of unit normal `normal` receives: its view factor to the
/// planet (–, the closed form), albedo and IR irradiance (W/m²; a uniform emitter's
/// flux times the view factor, the Sun-dependent parts by the rings).
PlanetChannels unobstructedPlanetLoads(const PlanetView& view, const Eigen::Vector3d& normal);

/// The rings of one position for the unobstructed loads of many normals (a curved part's
/// facets): the pieces between the position's own cuts (the cap's edge, the terminator,
/// the night floor) and their Gauss points are computed once; a normal's horizon splits
/// at most one piece, whose points it computes itself. loads(n) is
/// unobstructedPlanetLoads(view, n) to rounding (the same formulas, their products fused
/// differently by the compiler: 2e-15 of the largest load on the 1,602-node satellite) at
/// about two thirds of the cost (1.9 against 2.7 µs a normal at 700 km).
class PlanetRings {
 public:
  /// Where a wave a + b cos(φ − phase) along a ring is positive: |φ − phase| < half (half =
  /// π: everywhere; none: nowhere), with half's cosine and sine.
  struct Arc {
    bool none = false;
    double half = M_PI, cos_half = -1.0, sin_half = 0.0;
  };

  explicit PlanetRings(const PlanetView& view);
  PlanetChannels loads(const Eigen::Vector3d& normal) const;
  /// Σ_k shares_k loads(normals_k) over a facetted part's unit normals. A plane that sees
  /// the whole cap (n · c ≥ sin θ_max) receives n · ∫_cap L d dΩ, linear in n: those
  /// normals cost one ring integral together, at their weighted sum (its direction sees the
  /// whole cap too: the cone of such normals is convex). Normals facing away from the
  /// whole cap receive nothing; the rest one ring integral each.
  PlanetChannels facetLoads(const std::vector<Eigen::Vector3d>& normals, const std::vector<double>& shares) const;

 private:
  struct Point {
    double jacobian, cos_theta, sin_theta, sun_a, sun_b;  // the ring's weight, θ, the Sun's wave
    // The arcs of the Sun's wave (albedo) and of the warm ground's (cos z > c0): the same
    // for every normal, computed with the point (a third of a normal's cost was their acos).
    Arc sun_arc, warm_arc;
  };
  Point point(double g0, double g1, int q) const;
  PlanetView view_;
  Eigen::Vector3d e1_, e2_;
  double gamma_max_ = 0.0, theta_max_ = 0.0, psi_ = 0.0;
  double floor_ = 0.0, k_ = 0.0, c0_ = 0.0;  // the emission: floor + k max(0, cos z − c0)
  bool lit_ = false, warm_ = false;
  double sun_a_ = 0.0, sun_b_ = 0.0, sun_cos_ = 1.0, sun_sin_ = 0.0;  // the Sun in the ring frame
  std::vector<double> cuts_;  // sorted, the horizon left out
  std::vector<Point> points_;  // kGaussOrder per piece
};

}  // namespace radnet::orbits
