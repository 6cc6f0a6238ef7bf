#include "orbits/loads.hpp"

#include "geometry/irradiance/sun_grid.hpp"
#include "orbits/direct_loads.hpp"
#include "orbits/sky_loads.hpp"
#include "solver/units.hpp"

#include <algorithm>

#include <chrono>
#include <cmath>
#include <stdexcept>

namespace radnet::orbits {

double albedoAt(const EnvironmentOptions& opt, double lat) {
  const auto& t = opt.albedo_by_latitude;
  if (t.empty()) return opt.albedo;
  lat = std::abs(lat);
  if (lat <= t.front().first) return t.front().second;
  for (size_t k = 1; k < t.size(); ++k)
    if (lat <= t[k].first) {
      const double w = (lat - t[k - 1].first) / (t[k].first - t[k - 1].first);
      return (1 - w) * t[k - 1].second + w * t[k].second;
    }
  return t.back().second;
}

double shadowGridSpacing(const Eigen::VectorXd& area, double relative_error) {
  std::vector<double> a;
  for (Eigen::Index i = 0; i < area.size(); ++i)
    if (area[i] > 0) a.push_back(area[i]);
  if (a.empty()) return 1.0;
  const size_t q = a.size() / 10;
  std::nth_element(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(q), a.end());
  return geometry::sunGridSpacing(a[q], relative_error);
}

namespace {

// The mean and standard error of per-replica estimates.
void replicaStatistics(const std::vector<double>& estimates, double& value, double& stderr_value) {
  const double m = static_cast<double>(estimates.size());
  double sum = 0.0, sum2 = 0.0;
  for (double e : estimates) sum += e, sum2 += e * e;
  value = sum / m;
  stderr_value = m > 1 ? std::sqrt(std::max(0.0, (sum2 - m * value * value) / (m - 1)) / m) : value;
}

// Whether this process computes entry k (an empty mask: every entry).
bool mine(const std::vector<char>& mask, int k) { return mask.empty() || mask[static_cast<size_t>(k)]; }

// The albedo where the planet's outward unit normal (body frame) points: by latitude when
// the case gives a table.
double albedoAtPoint(const EnvironmentOptions& opt, const Eigen::Matrix3d& eciFromBody, const Eigen::Vector3d& normal) {
  if (opt.albedo_by_latitude.empty()) return opt.albedo;
  return albedoAt(opt, units::radToDeg(std::asin(std::clamp((eciFromBody * normal).z(), -1.0, 1.0))));
}

// Albedo and (for a planet whose emission follows the Sun) planet IR irradiance of one node
// and their σ from the replicas, W/m²: π Σ L w / N per replica, with the albedo's
// L = a S max(0, ŝ·n) / π and the IR's L = exitance(ŝ·n, S) / π at each hit.
void planetRadianceLoads(const geometry::PlanetRays& r, const Eigen::Vector3d& center, double re,
                         const SweepPosition& pos, const EnvironmentOptions& opt, int i, int p, EnvironmentLoads& out) {
  const Eigen::Matrix3d eciFromBody = pos.body_from_eci.transpose();
  const int replicas = static_cast<int>(r.replica_end.size());
  const bool ir_by_hit = !opt.planet_ir.uniform();
  if (replicas == 0 || r.rays == 0) {
    out.albedo(i, p) = out.albedo_stderr(i, p) = 0.0;
    if (ir_by_hit) out.earth_ir(i, p) = out.earth_ir_stderr(i, p) = 0.0;
    return;
  }
  const double per_replica = double(r.rays) / replicas, flux = pos.solar_flux_w_m2;
  std::vector<double> albedo(static_cast<size_t>(replicas)), ir(static_cast<size_t>(replicas));
  size_t k = 0;
  // A uniform albedo and IR (the common case): Σ w max(0, ŝ·n) per replica, ŝ·n = (ŝ·h − ŝ·c)/R
  // with no branch, which the compiler vectorises (the loads stage of the 1,602-node
  // satellite, 76 positions: 0.53 s with the general loop below, 0.40 s with this one).
  const bool uniform = !ir_by_hit && opt.albedo_by_latitude.empty();
  const double sun_at_center = pos.sun_body.dot(center), inv_re = 1.0 / re;
  for (int rep = 0; rep < replicas; ++rep) {
    double albedo_part = 0.0, ir_part = 0.0;
    const size_t end = static_cast<size_t>(r.replica_end[static_cast<size_t>(rep)]);
    if (uniform) {
      for (; k < end; ++k)
        albedo_part += std::max(0.0, (r.hit_points[k].dot(pos.sun_body) - sun_at_center) * inv_re) * r.weights[k];
      albedo[static_cast<size_t>(rep)] = flux * opt.albedo * albedo_part / per_replica;
      continue;
    }
    for (; k < end; ++k) {
      const Eigen::Vector3d normal = (r.hit_points[k] - center) / re;  // outward, body frame
      const double cos_sun = normal.dot(pos.sun_body);
      if (ir_by_hit) ir_part += opt.planet_ir.exitance(cos_sun, flux) * r.weights[k];
      if (cos_sun <= 0) continue;  // night side
      albedo_part += albedoAtPoint(opt, eciFromBody, normal) * cos_sun * r.weights[k];
    }
    albedo[static_cast<size_t>(rep)] = flux * albedo_part / per_replica;
    ir[static_cast<size_t>(rep)] = ir_part / per_replica;
  }
  replicaStatistics(albedo, out.albedo(i, p), out.albedo_stderr(i, p));
  if (ir_by_hit) replicaStatistics(ir, out.earth_ir(i, p), out.earth_ir_stderr(i, p));
  // One ray's worth at the planet's largest radiance where the spacecraft blocked some
  // (PlanetRays::one_ray_share): what the replicas' spread cannot see.
  if (r.one_ray_share > 0) {
    double brightest = opt.albedo_by_latitude.empty() ? opt.albedo : 0.0;
    for (const auto& [latitude, a] : opt.albedo_by_latitude) brightest = std::max(brightest, a);
    const double albedo_ray = flux * brightest * r.one_ray_share;
    out.albedo_stderr(i, p) = std::hypot(out.albedo_stderr(i, p), albedo_ray);
    if (ir_by_hit) out.earth_ir_stderr(i, p) = std::hypot(out.earth_ir_stderr(i, p), opt.planet_ir.maxExitance(flux) * r.one_ray_share);
  }
}

// Albedo (solar band) and planet IR (IR band) that mirrors and windows pass on, added to
// position p's loads with their σ from the replicas: each arrival brings L(hit) × weight,
// L the planet's radiance where the light left (a S max(0, cos z)/π, exitance/π).
void redirectedPlanetLoads(const geometry::RedirectedPlanetPaths& albedo_paths,
                           const geometry::RedirectedPlanetPaths& ir_paths, const Eigen::Vector3d& center, double re,
                           const Eigen::VectorXd& area, const SweepPosition& pos, const EnvironmentOptions& opt,
                           EnvironmentLoads& out, int p) {
  const double flux = pos.solar_flux_w_m2;
  const Eigen::Matrix3d eciFromBody = pos.body_from_eci.transpose();
  const auto add = [&](const geometry::RedirectedPlanetPaths& paths, bool albedo) {
    if (paths.arrivals.empty()) return;
    Eigen::MatrixXd by_replica = Eigen::MatrixXd::Zero(area.size(), paths.replicas);
    for (const geometry::RedirectedPlanetPaths::Arrival& a : paths.arrivals) {
      const Eigen::Vector3d normal = (paths.hit_points[static_cast<size_t>(a.hit)] - center) / re;
      const double cos_sun = normal.dot(pos.sun_body);
      const double exitance = albedo ? albedoAtPoint(opt, eciFromBody, normal) * flux * std::max(0.0, cos_sun)
                                     : opt.planet_ir.exitance(cos_sun, flux);
      by_replica(a.node, a.replica) += exitance / M_PI * a.weight;  // each replica estimates the whole
    }
    Eigen::MatrixXd& load = albedo ? out.albedo : out.earth_ir;
    Eigen::MatrixXd& sigma = albedo ? out.albedo_stderr : out.earth_ir_stderr;
    for (Eigen::Index i = 0; i < area.size(); ++i) {
      if (!mine(opt.planet_nodes, static_cast<int>(i))) continue;  // ranks join by owner: each adds its nodes'
      double value = 0.0, error = 0.0;
      const Eigen::VectorXd row = by_replica.row(i);
      replicaStatistics(std::vector<double>(row.data(), row.data() + row.size()), value, error);
      load(i, p) += value / area[i];
      sigma(i, p) = std::hypot(sigma(i, p), error / area[i]);
    }
  };
  add(albedo_paths, true);
  add(ir_paths, false);
}

// The cone rays and the specular paths of one planet position (body frame centre).
struct PlanetCast {
  std::vector<geometry::PlanetRays> rays;                  // per node (empty: not cast)
  geometry::RedirectedPlanetPaths albedo_paths, ir_paths;  // planet light that mirrors and windows pass on
  bool same_paths = false;                                 // the bands' ρs, τ agree: albedo_paths serve the IR too
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  int casts = 0;
};

// Whether the Earth sits where it did at the last cast (nadir pointing: reuse).
bool samePlace(const PlanetCast& cast, const Eigen::Vector3d& center) {
  return cast.casts > 0 && (center - cast.center).norm() <= 1e-9 * center.norm();
}

// Casts cone rays from the nodes `nodes` leaves in (into cast.rays, others kept).
void castConeRays(const geometry::RayCaster& caster, const Eigen::Vector3d& center, double re,
                  const EnvironmentOptions& opt, const std::vector<char>& nodes, PlanetCast& cast,
                  EnvironmentLoads& out) {
  geometry::PlanetRayOptions planet;
  planet.rays_per_node = opt.planet_rays > 0 ? opt.planet_rays : kMaxPlanetRays;
  planet.relative_error = opt.planet_rays > 0 ? 0.0 : opt.relative_error;
  planet.seed = opt.seed;
  planet.nodes = nodes;
  std::vector<geometry::PlanetRays> rays = geometry::planetRays(caster, center, re, planet);
  cast.rays.resize(rays.size());
  for (size_t i = 0; i < rays.size(); ++i)
    if (mine(nodes, static_cast<int>(i))) {
      out.planet_rays += rays[i].rays;
      cast.rays[i] = std::move(rays[i]);
    }
}

// The specular paths of the planet's light (nothing without mirrors or windows).
void castPlanetPaths(const geometry::RayCaster& caster, const Eigen::Vector3d& center, double re,
                     const EnvironmentOptions& opt, PlanetCast& cast, EnvironmentLoads& out) {
  cast.albedo_paths =
      geometry::redirectedPlanetPaths(caster, opt.solar_specular, center, re, opt.specular_samples, opt.seed);
  cast.same_paths = opt.ir_specular.sameAs(opt.solar_specular);
  cast.ir_paths = cast.same_paths ? geometry::RedirectedPlanetPaths{}
                                  : geometry::redirectedPlanetPaths(caster, opt.ir_specular, center, re,
                                                                    opt.specular_samples, opt.seed);
  out.planet_rays += cast.albedo_paths.rays + cast.ir_paths.rays;
}

// Position p's planet loads of the nodes `nodes` leaves in from their cone rays.
void coneLoads(const PlanetCast& cast, double re, const SweepPosition& pos, const EnvironmentOptions& opt,
               const std::vector<char>& nodes, int p, EnvironmentLoads& out) {
  // Nodes apart: each writes only its own entries of column p (the same numbers on any
  // number of threads). 76 positions × 2.3 M kept rays were 0.5 s of one core.
#pragma omp parallel for schedule(dynamic, 16)
  for (int i = 0; i < static_cast<int>(cast.rays.size()); ++i) {
    if (!mine(nodes, i)) continue;
    const geometry::PlanetRays& r = cast.rays[static_cast<size_t>(i)];
    out.earth_view_factor(i, p) = r.view_factor;
    if (opt.planet_ir.uniform()) {
      out.earth_ir(i, p) = opt.planet_ir.uniform_w_m2 * r.view_factor;
      out.earth_ir_stderr(i, p) = opt.planet_ir.uniform_w_m2 * r.standard_error;
    }
    planetRadianceLoads(r, cast.center, re, pos, opt, i, p, out);
  }
}

// The planet as the sky kernel sees it at one position.
PlanetView planetView(const SweepPosition& pos, double re, const EnvironmentOptions& opt) {
  PlanetView view;
  view.toward_center = pos.planet_body.normalized();
  view.distance_m = pos.planet_distance_m;
  view.radius_m = re;
  view.toward_sun = pos.sun_body.normalized();
  view.solar_flux_w_m2 = pos.solar_flux_w_m2;
  view.albedo = opt.albedo;
  view.ir = opt.planet_ir;
  return view;
}

// Whether the sky kernel serves this sweep: as the case's method asks (auto: when the planet
// moves in the body frame, or from kSkyKernelNodesPerPosition nodes a position), and not when the
// case pins planet rays, gives an albedo by latitude (the kernel's radiance is per
// direction, not per place), or the planet is so far that it covers little of a node's
// sky (rays into its cone do better; /report planet_load_method says which ran).
bool kernelServes(const std::vector<SweepPosition>& positions, bool earth_fixed, double re,
                  const EnvironmentOptions& opt, Eigen::Index nodes, double& smallest_cap_sin2) {
  smallest_cap_sin2 = 1.0;
  if (positions.empty()) return false;
  bool planet_still = earth_fixed;  // and where it sits stays put (not on an elliptic orbit)
  const Eigen::Vector3d first = positions.front().planet_body * positions.front().planet_distance_m;
  for (const SweepPosition& pos : positions) {
    smallest_cap_sin2 = std::min(smallest_cap_sin2, (re / pos.planet_distance_m) * (re / pos.planet_distance_m));
    const Eigen::Vector3d center = pos.planet_body * pos.planet_distance_m;
    planet_still = planet_still && (center - first).norm() <= 1e-9 * center.norm();
  }
  using Method = EnvironmentOptions::PlanetMethod;
  const bool many_nodes = nodes >= kSkyKernelNodesPerPosition * static_cast<Eigen::Index>(positions.size());
  const bool wanted =
      opt.planet_method == Method::SkyKernel || (opt.planet_method == Method::Auto && (!planet_still || many_nodes));
  return wanted && opt.planet_rays == 0 && opt.albedo_by_latitude.empty() && smallest_cap_sin2 >= kSkyKernelMinCapSin2;
}

// The sweep's planet loads from the sky kernel (cast once per geometry: kSkyKernelFirstRays
// a node, then more for the nodes over their target), cone rays only for the node-positions
// still over (cast once per node when the Earth is fixed).
void kernelPlanetLoads(const geometry::RayCaster& caster, const std::vector<SweepPosition>& positions, bool earth_fixed,
                       double re, double smallest_cap_sin2, const EnvironmentOptions& opt, const Eigen::MatrixXd& direct,
                       EnvironmentLoads& out) {
  geometry::SkyKernel local;
  geometry::SkyKernel& kernel = opt.sky_kernel_cache ? *opt.sky_kernel_cache : local;
  std::vector<PlanetView> views;
  for (const SweepPosition& pos : positions) views.push_back(planetView(pos, re, opt));
  const KernelTargets targets = kernelLoads(caster, views, smallest_cap_sin2, opt, direct, kernel, out);
  PlanetCast fallback;
  const size_t n = kernel.nodes.size();
  std::vector<char> have(n, 0), over(n, 0), need(n, 0);
  for (int p = 0; p < static_cast<int>(positions.size()); ++p) {
    const SweepPosition& pos = positions[static_cast<size_t>(p)];
    const Eigen::Vector3d center = pos.planet_body * pos.planet_distance_m;
    if (!(earth_fixed && samePlace(fallback, center))) std::fill(have.begin(), have.end(), 0);
    bool any = false;
    for (size_t i = 0; i < n; ++i) {
      over[i] = mine(opt.planet_nodes, static_cast<int>(i)) && kernel.nodes[i].rays > 0 &&
                targets.over(out, static_cast<Eigen::Index>(i), p) > kKernelFallbackRatio;
      out.kernel_fallbacks += over[i];
      need[i] = over[i] && !have[i];
      any = any || need[i];
    }
    if (any) {
      castConeRays(caster, center, re, opt, need, fallback, out);
      fallback.center = center;
      ++fallback.casts;
      for (size_t i = 0; i < n; ++i) have[i] = have[i] || need[i];
    }
    coneLoads(fallback, re, pos, opt, over, p, out);
  }
}

}  // namespace

EnvironmentLoads environmentLoads(const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                                  const std::vector<SweepPosition>& positions, bool earth_fixed, double re,
                                  const EnvironmentOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const int n = static_cast<int>(area.size());
  const int P = static_cast<int>(positions.size());
  EnvironmentLoads out;
  out.direct = out.albedo = out.earth_ir = out.earth_view_factor = Eigen::MatrixXd::Zero(n, P);
  out.direct_stderr = out.albedo_stderr = out.earth_ir_stderr = Eigen::MatrixXd::Zero(n, P);
  if (!opt.sun_positions.empty() && opt.sun_positions.size() != static_cast<size_t>(P))
    throw std::invalid_argument("environment loads: the position mask must have one entry per position");
  // The direct load first: the sky kernel's targets are shares of each node's absorbed power.
  LitCache lit(positions);
  directLoadsAt(caster, area, positions, opt, opt.sun_positions, out, lit);  // no rays in the umbra
  double smallest_cap_sin2 = 1.0;
  out.planet_kernel = kernelServes(positions, earth_fixed, re, opt, area.size(), smallest_cap_sin2);
  if (out.planet_kernel)
    kernelPlanetLoads(caster, positions, earth_fixed, re, smallest_cap_sin2, opt,
                      directAtEveryPosition(caster, area, positions, opt, out), out);
  PlanetCast cast;
  for (int p = 0; p < P; ++p) {
    const SweepPosition& pos = positions[static_cast<size_t>(p)];
    // Planet rays and paths: cast again unless the Earth sits where it did (reuse).
    const Eigen::Vector3d center = pos.planet_body * pos.planet_distance_m;
    if (!(earth_fixed && samePlace(cast, center))) {
      if (!out.planet_kernel) castConeRays(caster, center, re, opt, opt.planet_nodes, cast, out);
      castPlanetPaths(caster, center, re, opt, cast, out);
      cast.center = center;
      ++cast.casts;
    }
    if (!out.planet_kernel) coneLoads(cast, re, pos, opt, opt.planet_nodes, p, out);
    redirectedPlanetLoads(cast.albedo_paths, cast.same_paths ? cast.albedo_paths : cast.ir_paths, center, re, area,
                          pos, opt, out, p);
    if (opt.progress) opt.progress(p + 1, P);
  }
  out.planet_casts = out.planet_kernel ? 0 : cast.casts;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace radnet::orbits
