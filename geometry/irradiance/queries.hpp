#pragma once
// Ray-casting queries for the orbit stage (geometry/ knows nothing of orbits: directions
// and positions arrive in the body frame, metres).
#include "geometry/rays/ray_caster.hpp"

#include <Eigen/Dense>

#include <cstdint>
#include <vector>

namespace radnet::geometry {

/// Sunlit projection of every node for one direction.
struct LitArea {
  Eigen::VectorXd projected_m2;  ///< ∫ max(0, n·d) · visible dA per node, m² (times the flux gives W)
  Eigen::VectorXd lit_fraction;  ///< of the node's sunward-facing area not shadowed, – (0 when none faces)
  Eigen::VectorXd stderr_m2;     ///< standard error of projected_m2 as if the points were independent (an
                                 ///< upper bound for Sobol points), m²
  std::int64_t rays_cast = 0;    ///< shadow rays actually cast (nodes facing away cast none)
};

/// Projected lit area of every node for a collimated source in direction `toward_source`
/// (unit, body frame): `samples` area-uniform points per node (Sobol, shifted by `seed`),
/// each weighted by max(0, n·d) and tested with a shadow ray towards the source; the
/// node's exact unshadowed projection times the weighted lit share (a ratio estimate). Nodes
/// whose every triangle faces away cast no rays, nor those `only` leaves out (when given).
/// With `replicas` > 1 the samples are split into independently shifted Sobol sequences and
/// the error is their spread (randomised QMC), far below the independent-points bound.
LitArea litArea(const RayCaster& caster, const Vec3& toward_source, int samples, std::uint64_t seed = 1,
                const std::vector<char>& only = {}, int replicas = 1);

/// Rays from one node that reach a sphere (the planet) unobstructed by the spacecraft.
struct PlanetRays {
  double view_factor = 0.0;  ///< F from the node to the visible sphere, with self-shadowing, –
  double standard_error = 0.0;
  std::vector<Vec3> hit_points;  ///< where the unobstructed rays meet the sphere, body frame, m
  /// Each hit's weight Ω cos θ / π (Ω the sphere's solid angle, θ from the node's normal):
  /// F = Σ weights / rays, and any Lambertian radiance field L of the sphere gives the
  /// irradiance π Σ L(hit) weight / rays.
  std::vector<double> weights;
  std::vector<int> replica_end;  ///< hits of replica r end at replica_end[r] (rays/replicas rays each)
  std::int64_t rays = 0;
  /// One ray's largest share of F, Ω/(π N) (N = rays), where the spacecraft blocked some of
  /// them, else 0: a blocker thinner than the rays' spacing, or a sliver of the planet seen
  /// past one, can fall between the points of every replica, and their spread then says
  /// nothing of it (the inside of a tube seeing the limb through its end: F = 0 ± 0 from
  /// 1,024 rays for a true 0.0025). `standard_error` holds this term; the loads add it at
  /// their largest radiance (orbits/loads.cpp), as the sky kernel does.
  double one_ray_share = 0.0;
};

/// How many rays planetRays casts per node.
struct PlanetRayOptions {
  std::int64_t rays_per_node = 16384;  ///< fixed count, or the cap when relative_error > 0
  /// Target σ of each node's view factor relative to max(F, 0.1 sin² θ_max), the second
  /// term a tenth of the largest F any plate can have (θ_max: the sphere's angular radius);
  /// 0: cast exactly rays_per_node. Rays double from 1,024 until met or capped.
  double relative_error = 0.0;
  std::uint64_t seed = 1;
  /// Nodes that cast (empty: all); the others come out empty (0 rays, F = 0), for another
  /// process to cast. A node's rays depend only on (seed, node), not on this mask.
  std::vector<char> nodes;
};

/// Rays from every node into the cone the sphere subtends (uniform in solid angle, so a
/// far planet costs no more than a near one), Sobol points with 32 replicas for the error;
/// each ray facing out of the node is tested against the spacecraft (self-shadowing).
std::vector<PlanetRays> planetRays(const RayCaster& caster, const Vec3& sphere_center, double sphere_radius,
                                   const PlanetRayOptions& options);

/// The same with a fixed count per node.
std::vector<PlanetRays> planetRays(const RayCaster& caster, const Vec3& sphere_center, double sphere_radius,
                                   std::int64_t rays_per_node, std::uint64_t seed = 1);

}  // namespace radnet::geometry
