#pragma once
// Environment irradiances per node and sweep position (W/m², averaged over each node):
//  * direct solar: flux × sunlit fraction × lit projected area / A (shadowing by the rest
//    of the spacecraft through geometry/'s litArea; nodes facing away cast no rays);
//  * albedo: cosine-weighted planet rays of each node (self-shadowed), each ray hitting
//    the Earth at x carries a · S · max(0, ŝ·n(x)) (a Lambertian planet of radiance
//    a S cos θ_s / π, sampled with pdf cos θ/π);
//  * Earth IR: OLR × view factor to the Earth (uniform Lambertian emitter).
// Reuse: when the Earth is fixed in the body frame (nadir pointing on a circular orbit)
// the planet rays are cast once and their hit points reused; only the Sun's part changes.
#include "geometry/queries.hpp"
#include "orbits/sweep.hpp"

#include <Eigen/Dense>

#include <functional>
#include <vector>

namespace radnet::orbits {

struct EnvironmentOptions {
  double albedo =
      0.30;  ///< Bond albedo, – (orbit-average Earth value; Gilmore, Spacecraft Thermal Control Handbook, ch. 2)
  /// Optional latitude dependence: (|geocentric latitude| deg, albedo) pairs, linear in between.
  std::vector<std::pair<double, double>> albedo_by_latitude;
  double earth_ir_w_m2 = 237.0;      ///< outgoing longwave radiation, W/m² (global mean; Gilmore, ch. 2)
  int shadow_samples = 1024;         ///< points per node for direct-solar shadow rays
  std::int64_t planet_rays = 16384;  ///< cosine-weighted rays per node towards the planet
  std::uint64_t seed = 1;
  std::function<void(int, int)> progress;  ///< (positions done, positions total), optional
};

struct EnvironmentLoads {
  Eigen::MatrixXd direct;             ///< (n×P) direct solar irradiance, W/m²
  Eigen::MatrixXd albedo;             ///< (n×P) albedo irradiance, W/m²
  Eigen::MatrixXd earth_ir;           ///< (n×P) Earth IR irradiance, W/m²
  Eigen::MatrixXd earth_view_factor;  ///< (n×P) with self-shadowing, –
  int planet_casts = 0;               ///< how many times the planet rays were cast (1 with reuse)
  std::int64_t shadow_rays = 0;
  double seconds = 0.0;
};

/// @param node_area_m2 A per node (scene order)
EnvironmentLoads environmentLoads(const geometry::RayCaster& caster, const Eigen::VectorXd& node_area_m2,
                                  const std::vector<SweepPosition>& positions, bool earth_fixed_in_body,
                                  double earth_radius_m, const EnvironmentOptions& options);

/// The albedo of a geocentric latitude (deg) under the options.
double albedoAt(const EnvironmentOptions& options, double latitude_deg);

}  // namespace radnet::orbits
