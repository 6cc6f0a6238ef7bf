#pragma once
// Ray-casting queries for the orbit stage (geometry/ knows nothing of orbits: directions
// and positions arrive in the body frame, metres).
#include "geometry/ray_caster.hpp"

#include <Eigen/Dense>

#include <cstdint>
#include <vector>

namespace radnet::geometry {

/// Sunlit projection of every node for one direction.
struct LitArea {
  Eigen::VectorXd projected_m2;  ///< ∫ max(0, n·d) · visible dA per node, m² (times the flux gives W)
  Eigen::VectorXd lit_fraction;  ///< of the node's sunward-facing area not shadowed, – (0 when none faces)
  std::int64_t rays_cast = 0;    ///< shadow rays actually cast (nodes facing away cast none)
};

/// Projected lit area of every node for a collimated source in direction `toward_source`
/// (unit, body frame): `samples` area-uniform points per node (Sobol, shifted by `seed`),
/// each weighted by max(0, n·d) and tested with a shadow ray towards the source. Nodes
/// whose every triangle faces away cast no rays.
LitArea litArea(const RayCaster& caster, const Vec3& toward_source, int samples, std::uint64_t seed = 1);

/// Rays from one node that reach a sphere (the planet) unobstructed by the spacecraft.
struct PlanetRays {
  double view_factor = 0.0;  ///< fraction of the node's cosine-weighted rays reaching the sphere, –
  double standard_error = 0.0;
  std::vector<Vec3> hit_points;  ///< where those rays meet the sphere, body frame, m
  std::vector<Vec3> directions;  ///< their unit directions
  std::int64_t rays = 0;
};

/// Cosine-weighted rays from every node (Sobol, 32 replicas for the error): each ray is
/// first tested against the spacecraft (self-shadowing), then against the sphere.
std::vector<PlanetRays> planetRays(const RayCaster& caster, const Vec3& sphere_center, double sphere_radius,
                                   std::int64_t rays_per_node, std::uint64_t seed = 1);

/// Where a ray from `origin` along unit `dir` first meets a sphere (t > 0), if it does.
bool raySphere(const Vec3& origin, const Vec3& dir, const Vec3& center, double radius, Vec3& hit);

}  // namespace radnet::geometry
