#include "orbits/direct_loads.hpp"

#include "geometry/irradiance/sun_clip.hpp"
#include "geometry/irradiance/sun_grid.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::orbits {

namespace {

using OpenSides = std::vector<std::uint8_t>;  // geometry/scene/open_sides.hpp

// Sunlight that mirrors and windows pass on (the whole arrival at each node it reaches: the
// network takes its κ share, the tracer carries the rest on), added to the direct load.
void redirectedSunlight(const geometry::RayCaster& caster, const Eigen::VectorXd& area, const SweepPosition& pos,
                        const EnvironmentOptions& opt, double flux, EnvironmentLoads& out, int p) {
  if (!opt.solar_specular.anyRedirects()) return;
  const geometry::RedirectedLight light =
      geometry::redirectedCollimated(caster, opt.solar_specular, pos.sun_body, opt.specular_samples, opt.seed);
  out.direct.col(p) += flux * light.arrived_m2.cwiseQuotient(area);
  const Eigen::VectorXd sigma = flux * light.stderr_m2.cwiseQuotient(area);
  out.direct_stderr.col(p) = (out.direct_stderr.col(p).array().square() + sigma.array().square()).sqrt().matrix();
  out.shadow_rays += light.rays;
}

// The lit projection (m²) and its σ of every node at one position, by the case's method:
// exact clipping (the default), the shadow grid (shadow_cell_m) or per-node rays.
void litProjectionOnce(const geometry::RayCaster& caster, const SweepPosition& pos, const EnvironmentOptions& opt,
                       const OpenSides& open, Eigen::VectorXd& projected_m2, Eigen::VectorXd& stderr_m2,
                       EnvironmentLoads& out) {
  if (opt.shadow_samples > 0) {
    geometry::LitArea lit = geometry::litArea(caster, pos.sun_body, opt.shadow_samples, opt.seed);
    out.shadow_rays += lit.rays_cast;
    projected_m2 = std::move(lit.projected_m2), stderr_m2 = std::move(lit.stderr_m2);
    return;
  }
  geometry::SunlitArea lit;
  if (opt.shadow_cell_m > 0) {
    geometry::SunGridOptions grid;
    grid.cell_m = opt.shadow_cell_m;
    grid.seed = opt.seed;
    grid.negligible_fraction = opt.relative_error;
    grid.max_relative_stderr = opt.relative_error;
    lit = geometry::sunlitArea(caster, pos.sun_body, grid);
    out.shadow_rays += lit.cells + lit.node_rays;
    out.shadow_cell_m = lit.cell_m;
  } else {
    geometry::ExactSunOptions exact;
    if (!open.empty()) exact.open_sides = &open;
    lit = geometry::exactSunlitArea(caster.scene(), pos.sun_body, exact);
  }
  projected_m2 = std::move(lit.projected_m2), stderr_m2 = std::move(lit.stderr_m2);
}

void litProjection(const geometry::RayCaster& caster, const SweepPosition& pos, const EnvironmentOptions& opt,
                   const OpenSides& open, Eigen::VectorXd& projected_m2, Eigen::VectorXd& stderr_m2,
                   EnvironmentLoads& out, LitCache& cache) {
  const bool exact = opt.shadow_samples <= 0 && !(opt.shadow_cell_m > 0);  // no rays to count twice across ranks
  if (!exact || !cache.serves(pos))
    return litProjectionOnce(caster, pos, opt, open, projected_m2, stderr_m2, out);
  if (cache.projected_m2.size() == 0)
    litProjectionOnce(caster, cache.first, opt, open, cache.projected_m2, cache.stderr_m2, out);
  projected_m2 = cache.projected_m2, stderr_m2 = cache.stderr_m2;
}

// Direct irradiance and its σ at one lit position, W/m².
void directLoads(const geometry::RayCaster& caster, const Eigen::VectorXd& area, const SweepPosition& pos,
                 const EnvironmentOptions& opt, const OpenSides& open, EnvironmentLoads& out, int p, LitCache& cache) {
  const double flux = pos.solar_flux_w_m2 * pos.sunlit_fraction;
  Eigen::VectorXd projected_m2, stderr_m2;
  litProjection(caster, pos, opt, open, projected_m2, stderr_m2, out, cache);
  out.direct.col(p) = flux * projected_m2.cwiseQuotient(area);
  out.direct_stderr.col(p) = flux * stderr_m2.cwiseQuotient(area);
  redirectedSunlight(caster, area, pos, opt, flux, out, p);
}

}  // namespace

void directLoadsAt(const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                   const std::vector<SweepPosition>& positions, const EnvironmentOptions& opt,
                   const std::vector<char>& wanted, EnvironmentLoads& out, LitCache& cache) {
  std::vector<int> lit;
  for (int p = 0; p < static_cast<int>(positions.size()); ++p)
    if (positions[static_cast<size_t>(p)].sunlit_fraction > 0 && (wanted.empty() || wanted[static_cast<size_t>(p)]))
      lit.push_back(p);
  const bool exact = opt.shadow_samples <= 0 && !(opt.shadow_cell_m > 0) && !opt.solar_specular.anyRedirects();
#ifdef _OPENMP
  const bool parallel = exact && static_cast<int>(lit.size()) >= 2 * omp_get_max_threads();
#else
  const bool parallel = false;
#endif
  // The scene's open sides (found once per geometry; exact clipping skips their search).
  const bool clipped = opt.shadow_samples <= 0 && !(opt.shadow_cell_m > 0);
  static const OpenSides none;
  const OpenSides& open = clipped && !lit.empty() ? caster.openSides() : none;
  if (!parallel) {
    for (const int p : lit) directLoads(caster, area, positions[static_cast<size_t>(p)], opt, open, out, p, cache);
    return;
  }
  // The shared projection first, if any position takes it: the loop only reads the cache.
  bool shared = false;
  for (const int p : lit) shared = shared || cache.serves(positions[static_cast<size_t>(p)]);
  if (shared && cache.projected_m2.size() == 0)
    litProjectionOnce(caster, cache.first, opt, open, cache.projected_m2, cache.stderr_m2, out);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int k = 0; k < static_cast<int>(lit.size()); ++k)
    directLoads(caster, area, positions[static_cast<size_t>(lit[static_cast<size_t>(k)])], opt, open, out,
                lit[static_cast<size_t>(k)], cache);
}

// Every position's direct irradiance (n × P, W/m²): `out`'s where this process computed
// it, the rest (other processes' positions) computed here too, so that whatever reads it
// (the sky kernel's targets) is the same on any number of processes.
Eigen::MatrixXd directAtEveryPosition(const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                                      const std::vector<SweepPosition>& positions, const EnvironmentOptions& opt,
                                      const EnvironmentLoads& out) {
  if (opt.sun_positions.empty()) return out.direct;
  EnvironmentLoads others;
  others.direct = out.direct;
  others.direct_stderr = out.direct_stderr;
  LitCache cache(positions);
  std::vector<char> theirs(opt.sun_positions.size());
  for (size_t p = 0; p < theirs.size(); ++p) theirs[p] = !opt.sun_positions[p];
  directLoadsAt(caster, area, positions, opt, theirs, others, cache);
  return others.direct;
}

}  // namespace radnet::orbits
