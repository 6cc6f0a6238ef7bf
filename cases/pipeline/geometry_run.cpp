#include "cases/pipeline/geometry_run.hpp"

#include "cases/pipeline/orbit_sweep.hpp"
#include "cases/pipeline/progress.hpp"
#include "cases/pipeline/radiative_network.hpp"
#include "cases/pipeline/thermal_run.hpp"
#include "geometry/contour_view_factors.hpp"
#include "geometry/view_factors.hpp"
#include "solver/policy.hpp"

#include <ostream>

namespace radnet::cases {
namespace {

// F by ray casting or contour integration, then the variance-weighted reciprocity and
// closure correction (docs/geometry.md).
void viewFactorStage(const GeometryCase& c, const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                     GeometryRunResult& r, bool show_progress, std::ostream& progress) {
  const Eigen::Index n = area.size();
  StageTimer timer(r.timings, Stage::ViewFactors);
  Eigen::VectorXd rays(n);
  if (c.view_factors.method == ViewFactorMethod::MonteCarlo) {
    geometry::ViewFactorOptions opt = c.view_factors.monte_carlo;
    if (show_progress) opt.progress = progressBar(progress, "view factors", "nodes");
    const geometry::ViewFactorResult vf = geometry::computeViewFactors(caster, opt);
    r.raw_view_factors = vf.denseViewFactors();
    r.view_factor_stderr = vf.denseStandardError();
    for (Eigen::Index i = 0; i < n; ++i) rays[i] = double(vf.rays[static_cast<size_t>(i)]);
    r.total_rays = vf.total_rays;
    r.rays_per_second = vf.seconds > 0 ? double(vf.total_rays) / vf.seconds : 0.0;
    r.correction = geometry::enforceReciprocity(area, vf, rays);
  } else {
    const geometry::ContourResult det = geometry::contourViewFactors(caster, c.view_factors.contour);
    r.raw_view_factors = det.view_factors;
    r.view_factor_stderr = det.error_estimate;
    // Quadrature: a resolution of 1e6 "rays" makes the variance floor negligible.
    rays.setConstant(1e6);
    geometry::ViewFactorEstimate estimate;
    estimate.view_factors = det.view_factors.sparseView();
    estimate.standard_error = det.error_estimate.sparseView();
    estimate.space = det.space;
    estimate.space_error = estimate.blocked = estimate.blocked_error = Eigen::VectorXd::Zero(n);
    r.correction = geometry::enforceReciprocity(area, estimate, rays);
  }
  timer.stop();
  progress << "radnet: view factors: " << r.total_rays << " rays"
           << (r.rays_per_second > 0 ? " (" + std::to_string(static_cast<long long>(r.rays_per_second)) + " rays/s)"
                                     : "")
           << ", reciprocity/closure correction moved F by at most " << r.correction.max_change << " ("
           << r.correction.max_change_sigma << " σ)\n";
}

// The network from the corrected F, stored sparse or dense by the solver policy.
std::unique_ptr<solver::Network> buildNetwork(const GeometryCase& c, const Eigen::VectorXd& area,
                                              const geometry::ReciprocityCorrection& correction) {
  const int n = static_cast<int>(area.size());
  const auto tol = solver::policy::kCorrectedNetworkTolerances;
  const Eigen::SparseMatrix<double> f = correction.view_factors;
  if (solver::policy::storeSparse(correction.view_factors.nonZeros(), n))
    return std::make_unique<solver::Network>(c.node_names, area, f, correction.blocked, tol);
  return std::make_unique<solver::Network>(c.node_names, area, Eigen::MatrixXd(f), correction.blocked, tol);
}

}  // namespace

GeometryRunResult runGeometryCase(const GeometryCase& c, bool show_progress, std::ostream& progress) {
  GeometryRunResult r;
  const geometry::Scene& scene = c.scene;
  const int n = static_cast<int>(scene.nodes().size());
  for (const auto& w : scene.warnings()) progress << "radnet: warning: " << w << "\n";
  progress << "radnet: scene of " << scene.faces().size() << " triangles, " << n << " nodes\n";
  const Eigen::VectorXi front = scene.frontNodes(), back = scene.backNodes();
  r.triangle_node = front.binaryExpr(back, [](int f, int b) { return f >= 0 ? f : b; });
  StageTimer t_tree(r.timings, Stage::AabbTree);
  const geometry::RayCaster caster(scene);
  t_tree.stop();

  Eigen::VectorXd area(n);
  for (int i = 0; i < n; ++i) area[i] = scene.nodes()[static_cast<size_t>(i)].area_m2;
  viewFactorStage(c, caster, area, r, show_progress, progress);
  StageTimer t_net(r.timings, Stage::Network);
  r.radiative.network = buildNetwork(c, area, r.correction);
  t_net.stop();

  const Eigen::VectorXd rho_max =
      (Eigen::VectorXd::Ones(n) - c.emissivity).cwiseMax(Eigen::VectorXd::Ones(n) - c.absorptivity);
  r.radiative.pairs = decomposeNetwork(*r.radiative.network, rho_max, c.solver, r.timings);
  r.radiative.exchange = exchangeFactors(r.radiative, c.emissivity, c.solver, r.timings);
  if (c.orbit)
    r.sweep = runSweep({*c.orbit, caster, r.radiative, c.absorptivity, c.emissivity, c.solver}, r.timings,
                       show_progress, progress);
  if (c.thermal)
    r.thermal = runThermal(*c.thermal, *r.radiative.exchange, r.sweep ? &*r.sweep : nullptr, r.timings, progress);
  return r;
}

}  // namespace radnet::cases
