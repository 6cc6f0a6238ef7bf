#pragma once
// Environment irradiances per node and sweep position (W/m², averaged over each node):
//  * direct solar: flux × sunlit fraction × lit projected area / A, the lit projection
//    exact by polygon clipping (geometry/irradiance/sun_clip); with shadow_cell_m set, from
//    one grid of rays along the Sun's direction (sun_grid), with shadow_samples from each
//    node's own shadow rays (litArea);
//  * albedo and planet IR (a Lambertian planet of radiance a S cos θ_s / π, and the
//    emission's exitance / π): by default from the sky kernel (geometry/irradiance/
//    sky_kernel, orbits/sky_loads): each node's blocked (or open) sky is cast once per
//    geometry, and each position's load is the unobstructed plate's exact ring integral
//    (orbits/planet_sky) less the planet's radiance over the blocked bins, whatever the
//    attitude; node-positions whose kernel error exceeds the target, and cases the kernel
//    does not serve (pinned planet_rays, an albedo by latitude, a planet covering less than
//    kSkyKernelMinCapSin2), use planet rays: each node's rays (self-shadowed) into the cone
//    the planet subtends, each hit at x carrying the radiance there.
// Every load comes with its standard error (n×P, W/m²), and the ray counts follow
// relative_error (the loads' share of the case's error budget) unless pinned.
// Reuse: when the Earth is fixed in the body frame (nadir pointing on a circular orbit)
// the planet rays are cast once and their hit points reused; only the Sun's part changes.
// The sky kernel needs no reuse: it is cast once for every attitude.
#include "geometry/irradiance/queries.hpp"
#include "geometry/rays/specular.hpp"
#include "orbits/body.hpp"
#include "orbits/sweep.hpp"

#include <Eigen/Dense>

#include <cstdint>

#include <functional>
#include <vector>

namespace radnet::geometry {
struct SkyKernel;
}

namespace radnet::orbits {

/// Per node, the smallest α/ε and ε/α over every optical set some loads may serve (empty:
/// not known, e.g. optics sampled or following temperature). With them the sky kernel's
/// targets are shares of the absorbed power's lower bound α(D + A) + ε I rather than of
/// each channel alone (orbits/sky_loads.hpp, KernelTargets).
struct AbsorptanceRatios {
  Eigen::VectorXd min_alpha_over_epsilon, min_epsilon_over_alpha;  ///< –
  /// ≤ 1: the smallest ratio of one load's scale to another's (direct to albedo, IR to
  /// albedo, direct to IR, albedo to IR) over the design cases that reuse these loads
  /// scaled (a hot case's solar constant, albedo and IR): each cross term of the targets
  /// is weighted by it, so they hold in every such case. 1 when none does.
  double cross_weight = 1.0;
};

struct EnvironmentOptions {
  double albedo =
      0.30;  ///< Bond albedo, – (orbit-average Earth value; Gilmore, Spacecraft Thermal Control Handbook, ch. 2)
  /// Optional latitude dependence: (|geocentric latitude| deg, albedo) pairs, linear in between.
  std::vector<std::pair<double, double>> albedo_by_latitude;
  PlanetIr planet_ir;  ///< what the planet emits (default: the Earth's OLR, 237 W/m², Gilmore, ch. 2)
  /// Target standard error of each load relative to its scale (direct: the node's area
  /// times the flux; planet: see geometry::PlanetRayOptions), –
  double relative_error = 0.005;
  int shadow_samples = 0;      ///< > 0: this many shadow rays per node instead of the grid
  double shadow_cell_m = 0.0;  ///< > 0: shadow by a grid of rays of this spacing, m; 0: exact clipping
  std::int64_t planet_rays = 0;  ///< > 0: this many rays per node; 0: by relative_error up to kMaxPlanetRays
  /// How the planet loads are computed: Auto: the sky kernel when the planet moves in the
  /// body frame (it is cast once for every attitude), planet rays cast once when it stays
  /// put (nadir on a circular orbit: fewer rays than the kernel's whole sky); SkyKernel,
  /// Rays: always that one (where the kernel serves).
  enum class PlanetMethod { Auto, SkyKernel, Rays } planet_method = PlanetMethod::Auto;
  /// Where to keep the sky kernel between calls (several orbit cases of one geometry):
  /// built when empty, reused otherwise. nullptr: built for this call only.
  geometry::SkyKernel* sky_kernel_cache = nullptr;
  /// Each node's blocked share of its sky, cosine-weighted (1 − F_space from the view
  /// factors), and its σ (empty: not known). With it the sky kernel has only to split the
  /// share between the planet's cap and the rest (a ratio estimate: exact where every
  /// blocker lies inside the cap or outside it); a node whose kernel disagrees with it by
  /// more than 5σ keeps its own estimate.
  Eigen::VectorXd blocked_share, blocked_share_stderr;
  AbsorptanceRatios absorptance;  ///< empty: not known
  std::uint64_t seed = 1;
  /// Positions whose direct load, and nodes whose planet loads (albedo, Earth IR, Earth view
  /// factor), this process computes (empty: all). The rest stay 0 for other processes to
  /// fill (docs/mpi.md); each value depends only on the seed and its position and node.
  std::vector<char> sun_positions, planet_nodes;
  std::function<void(int, int)> progress;  ///< (positions done, positions total), optional
  /// The solar band's specular reflectance and transmittance per node (empty: none): direct
  /// sunlight they redirect is traced on to what it reaches (geometry::redirectedCollimated).
  geometry::SpecularBand solar_specular;
  /// The IR band's (empty: none): planet IR through mirrors and windows (albedo follows the
  /// solar band's).
  geometry::SpecularBand ir_specular;
  /// Sample points per redirecting node and lit position (16 replicas): a node's redirected
  /// beam is one smooth term (no shadow edge within a flat mirror), 1,024 points put its
  /// σ near 1e-3 of the beam where part of it is shadowed.
  int specular_samples = 1024;
};

/// The cap on planet rays per node when they follow the error target.
inline constexpr std::int64_t kMaxPlanetRays = 65536;
/// With the planet fixed in the body frame (nadir), `auto` takes the sky kernel from this
/// many nodes a position on, planet rays (cast once) below. The kernel's sweep costs some
/// 2 ms a position (its radiance tables, a curved node's rings, the nodes' sums) and its
/// rays less than the planet rays at the same accuracy (about 600 kernel rays a node
/// against 1,440 planet rays on the bench satellites). Measured, nadir, 76 positions (loads,
/// s, planet rays / kernel, best of three, 2026-12-07): the bench satellite at 402 nodes
/// 0.19 / 0.30, 786 nodes 0.30 / 0.31, 1,602 nodes 0.41 / 0.33, 2,306 nodes 0.61 / 0.53:
/// even at ~10 nodes a position (32 before the kernel's cast and tables got cheaper).
inline constexpr int kSkyKernelNodesPerPosition = 12;
/// The sky kernel serves planets whose angular radius θ_max has sin² θ_max at least this
/// (the Earth below 7,900 km altitude); a farther planet fills too little of a node's sky
/// for cosine-weighted rays, and rays into its cone do better.
inline constexpr double kSkyKernelMinCapSin2 = 0.2;

/// The shadow grid spacing (m) for nodes of these areas that the runs used before exact
/// clipping (bench/bench_direct_sun compares the two): the 10th-percentile node gets the
/// target relative error (geometry::sunGridSpacing).
double shadowGridSpacing(const Eigen::VectorXd& node_area_m2, double relative_error);

struct EnvironmentLoads {
  Eigen::MatrixXd direct;             ///< (n×P) direct solar irradiance, W/m²
  Eigen::MatrixXd albedo;             ///< (n×P) albedo irradiance, W/m²
  Eigen::MatrixXd earth_ir;           ///< (n×P) planet IR irradiance (the central body's; named for the Earth), W/m²
  Eigen::MatrixXd earth_view_factor;  ///< (n×P) to the central body, with self-shadowing, –
  Eigen::MatrixXd direct_stderr, albedo_stderr, earth_ir_stderr;  ///< standard errors of the three, W/m² (n×P)
  bool planet_kernel = false;         ///< the planet loads came from the sky kernel
  std::int64_t kernel_rays = 0;       ///< rays the sky kernel cast (once per geometry)
  double kernel_seconds = 0.0;        ///< time casting the sky kernel, s
  std::int64_t kernel_fallbacks = 0;  ///< node-positions whose kernel error needed planet rays
  int planet_casts = 0;               ///< how many times the planet rays were cast for all nodes (1 with reuse)
  std::int64_t planet_rays = 0;       ///< rays cast towards the planet, all casts
  std::int64_t shadow_rays = 0;       ///< shadow grid cells plus per-node shadow rays, all positions
  double shadow_cell_m = 0.0;         ///< the grid spacing of the last lit position (0: per-node rays), m
  double seconds = 0.0;
};

/// @param node_area_m2 A per node (scene order)
EnvironmentLoads environmentLoads(const geometry::RayCaster& caster, const Eigen::VectorXd& node_area_m2,
                                  const std::vector<SweepPosition>& positions, bool earth_fixed_in_body,
                                  double earth_radius_m, const EnvironmentOptions& options);

/// The albedo of a geocentric latitude (deg) under the options.
double albedoAt(const EnvironmentOptions& options, double latitude_deg);

}  // namespace radnet::orbits
