#include "orbits/sky_loads.hpp"

// The sky kernel's rounds: the first cast, the nodes' targets over the sweep, the re-casts
// of the nodes over them (orbits/sky_loads.hpp, kernelLoads).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace radnet::orbits {

namespace {

// Each node's smallest α/ε (or ε/α) over the optical sets, 0 where not known.
double ratioOf(const Eigen::VectorXd& ratios, Eigen::Index i) {
  return ratios.size() > i && std::isfinite(ratios[i]) ? std::max(0.0, ratios[i]) : 0.0;
}

KernelTargets kernelTargets(const EnvironmentLoads& out, const std::vector<PlanetView>& views,
                            double smallest_cap_sin2, const EnvironmentOptions& opt, const Eigen::MatrixXd& direct) {
  const double share = 0.5 * opt.relative_error, floor_view = 0.1 * smallest_cap_sin2;
  double flux = 0.0;
  for (const PlanetView& view : views) flux = std::max(flux, view.solar_flux_w_m2);
  const double floor_albedo = floor_view * opt.albedo * flux, floor_ir = floor_view * opt.planet_ir.maxExitance(flux);
  if (direct.rows() != out.albedo.rows() || direct.cols() != out.albedo.cols())
    throw std::invalid_argument("sky kernel targets: the direct irradiance must be n × P");
  const double w = std::clamp(opt.absorptance.cross_weight, 0.0, 1.0);
  KernelTargets t;
  for (Eigen::Index i = 0; i < out.albedo.rows(); ++i) {
    const Eigen::ArrayXd d = direct.row(i).transpose(), a = out.albedo.row(i).transpose();
    const Eigen::ArrayXd ir = out.earth_ir.row(i).transpose();
    const double r_alpha = w * ratioOf(opt.absorptance.min_alpha_over_epsilon, i);
    const double r_epsilon = w * ratioOf(opt.absorptance.min_epsilon_over_alpha, i);
    t.albedo.push_back(share * std::max((w * d + a + r_epsilon * ir).maxCoeff(), floor_albedo));
    t.ir.push_back(share * std::max((r_alpha * (d + a) + ir).maxCoeff(), floor_ir));
  }
  return t;
}

// What more rays can do at one node-position: 1/u for the factor u < 1 on both channels'
// sampling σ that brings σ_A / T_A + σ_I / T_I down to 2 (KernelTargets); 0 when the sum is
// within already, or when nothing rays can do (the binning errors, which more rays leave,
// are 99.5 % of it alone, or a channel is over a target of 0: that node-position is the
// fallback's). The sum is monotone in u: 50 halvings find u to 1e-15. With one channel
// alone this is its sampling σ over the room its binning leaves in twice its target.
double samplingRatio(const std::array<double, 2>& sigma, const std::array<double, 2>& binning,
                     const std::array<double, 2>& target) {
  std::array<double, 2> sampling{}, floor{};
  double now = 0.0;  // the sum at u = 1, σ over its target per channel
  for (size_t c = 0; c < 2; ++c) {
    if (!(target[c] > 0)) {
      if (sigma[c] > 0) return 0.0;
      continue;
    }
    now += sigma[c] / target[c];
    sampling[c] = std::sqrt(std::max(0.0, sigma[c] * sigma[c] - binning[c] * binning[c])) / target[c];
    floor[c] = binning[c] / target[c];
  }
  if (now <= 2.0 || floor[0] + floor[1] >= 0.995 * 2.0) return 0.0;
  const auto sum = [&](double u) {
    return std::hypot(sampling[0] * u, floor[0]) + std::hypot(sampling[1] * u, floor[1]);
  };
  double lo = 0.0, hi = 1.0;  // sum(lo) < 2 < sum(hi)
  for (int k = 0; k < 50; ++k) {
    const double mid = 0.5 * (lo + hi);
    (sum(mid) <= 2.0 ? lo : hi) = mid;
  }
  return 1.0 / std::max(lo, 1e-12);
}

// The rays each node over its target somewhere in the sweep asks for, 0 for the nodes
// within: its present count times its worst ratio to the power 4/3, at least 1.25× it, in
// whole replicas up to kMaxPlanetRays (doubling overshot: a node 10 % over its target took
// twice the rays it needed). Monte Carlo's σ ∝ N^(−1/2) would ask the ratio
// squared; the kernel's Sobol points do better (σ ∝ N^(−0.9) measured on the 1,602-node
// satellite: a ratio of 5 met by 32× the rays), so the square overshoots, and a node still
// over is cast again in the next round.
std::vector<std::int64_t> refinedRays(const geometry::SkyKernel& kernel, const EnvironmentLoads& out,
                                      const BinningErrors& binning, const KernelTargets& t,
                                      const std::vector<char>& candidates) {
  const Eigen::Index n = out.albedo.rows();
  const int P = static_cast<int>(out.albedo.cols());
  std::vector<std::int64_t> rays(static_cast<size_t>(n), 0);
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::int64_t present = kernel.nodes[static_cast<size_t>(i)].rays;
    if (!candidates[static_cast<size_t>(i)] || present <= 0 || present >= kMaxPlanetRays) continue;
    double worst = 0.0;
    for (int p = 0; p < P; ++p)
      worst = std::max(worst, samplingRatio({out.albedo_stderr(i, p), out.earth_ir_stderr(i, p)},
                                            {binning.albedo(i, p), binning.ir(i, p)},
                                            {t.albedo[static_cast<size_t>(i)], t.ir[static_cast<size_t>(i)]}));
    // A node partly blocked is not judged on the spread of 32 replicas of 32 rays: where a
    // thin blocker meets a few rays of each, that spread is itself too uncertain (a node
    // reported 54.50 ± 0.39 W/m² at 1,024 rays against 52.09 ± 0.02). From kMinPartlyBlockedRays
    // on it is (on the 1,602-node satellite, inertial, against a run at 20× the accuracy:
    // abs(Δ)/σ over 4 at 0.41 % of node-positions with 4,096 a node, 3.1 % with 1,024).
    // Rays drawn in a region of the sky (geometry/irradiance/sky_region) are that much
    // denser where blockers can be: the floor counts them by the hemisphere's worth they
    // stand for.
    const double b = kernel.nodes[static_cast<size_t>(i)].blocked_fraction;
    const double floor_rays = kMinPartlyBlockedRays * kernel.nodes[static_cast<size_t>(i)].ray_share;
    const bool partly = b > 0.0 && b < 1.0 && static_cast<double>(present) < floor_rays;
    if (worst <= 1.0 && !partly) continue;
    const double wanted = std::max(static_cast<double>(present) * std::pow(worst, 4.0 / 3.0), partly ? floor_rays : 0.0);
    const double more = std::min(std::max(1.25 * static_cast<double>(present), wanted), double(kMaxPlanetRays));
    const std::int64_t r = (static_cast<std::int64_t>(std::ceil(more)) + 31) / 32 * 32;
    rays[static_cast<size_t>(i)] = std::min(r, kMaxPlanetRays);
  }
  return rays;
}

// Casts again, with what their error asks, the nodes over their target, and recomputes their
// loads at every position; rounds until every node is within or at kMaxPlanetRays.
void refineKernel(const geometry::RayCaster& caster, const std::vector<PlanetView>& views,
                  SkySweepMemory& memory, const EnvironmentOptions& opt, const KernelTargets& targets,
                  geometry::SkyKernel& kernel, EnvironmentLoads& out, BinningErrors& binning) {
  std::vector<char> candidates(kernel.nodes.size(), 0);
  for (size_t i = 0; i < candidates.size(); ++i) candidates[i] = opt.planet_nodes.empty() || opt.planet_nodes[i];
  for (;;) {
    geometry::SkyKernelOptions k;
    k.seed = opt.seed;
    k.node_rays = refinedRays(kernel, out, binning, targets, candidates);
    k.prefix = &kernel;  // the nodes resume their Sobol points: only the new rays are traced
    if (std::none_of(k.node_rays.begin(), k.node_rays.end(), [](std::int64_t r) { return r > 0; })) return;
    const auto t0 = std::chrono::steady_clock::now();
    geometry::SkyKernel more = geometry::skyKernel(caster, k);
    for (size_t i = 0; i < kernel.nodes.size(); ++i) {
      candidates[i] = k.node_rays[i] > 0;
      if (!candidates[i]) continue;
      kernel.rays += more.nodes[i].rays - kernel.nodes[i].rays;
      kernel.nodes[i] = std::move(more.nodes[i]);
    }
    out.kernel_rays += more.cast_rays;
    out.kernel_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    skyKernelSweep(kernel, views, memory, candidates, opt.blocked_share, opt.blocked_share_stderr, out, &binning);
  }
}

}  // namespace

double KernelTargets::over(const EnvironmentLoads& out, Eigen::Index i, int p) const {
  const size_t k = static_cast<size_t>(i);
  const auto ratio = [](double sigma, double target) { return target > 0 ? sigma / target : (sigma > 0 ? 1e300 : 0.0); };
  return 0.5 * (ratio(out.albedo_stderr(i, p), albedo[k]) + ratio(out.earth_ir_stderr(i, p), ir[k]));
}

KernelTargets kernelLoads(const geometry::RayCaster& caster, const std::vector<PlanetView>& views,
                          double smallest_cap_sin2, const EnvironmentOptions& opt, const Eigen::MatrixXd& direct,
                          geometry::SkyKernel& kernel, EnvironmentLoads& out) {
  const bool fresh = kernel.nodes.empty();
  if (fresh) {
    geometry::SkyKernelOptions k;
    k.max_rays_per_node = kSkyKernelFirstRays;
    k.rays_per_share = static_cast<double>(kMinPartlyBlockedRays);
    k.seed = opt.seed;
    k.nodes = opt.planet_nodes;
    const auto t0 = std::chrono::steady_clock::now();
    kernel = geometry::skyKernel(caster, k);
    out.kernel_rays += kernel.cast_rays;
    out.kernel_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  SkySweepMemory memory;
  BinningErrors binning{Eigen::MatrixXd::Zero(out.albedo.rows(), out.albedo.cols()),
                        Eigen::MatrixXd::Zero(out.albedo.rows(), out.albedo.cols())};
  skyKernelSweep(kernel, views, memory, opt.planet_nodes, opt.blocked_share, opt.blocked_share_stderr, out,
                 &binning);
  const KernelTargets targets = kernelTargets(out, views, smallest_cap_sin2, opt, direct);
  if (fresh) refineKernel(caster, views, memory, opt, targets, kernel, out, binning);
  return targets;
}

}  // namespace radnet::orbits
