#include "cases/pipeline/geometry_run.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/config/error_budget.hpp"
#include "cases/pipeline/articulated.hpp"
#include "cases/pipeline/design_run.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/optical_uncertainty.hpp"
#include "cases/pipeline/progress.hpp"
#include "cases/pipeline/radiative_network.hpp"
#include "cases/pipeline/shared_rows.hpp"
#include "cases/pipeline/view_factor_rows.hpp"
#include "geometry/exact/view_factors.hpp"
#include "geometry/rays/specular.hpp"
#include "geometry/rays/view_factors.hpp"
#include "solver/radiative/policy.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <utility>
#include <memory>
#include <ostream>

namespace radnet::cases {
namespace {


// Per node, the largest reflectance of either band under any optical set, and under the
// samples of `uncertainty:` to 4σ.
Eigen::VectorXd largestReflectance(const GeometryCase& c) {
  const Eigen::Index n = c.emissivity.size();
  double margin_e = 0.0, margin_a = 0.0;
  if (c.optical_uncertainty) {
    margin_e = 4.0 * c.optical_uncertainty->emissivity_sigma;
    margin_a = 4.0 * c.optical_uncertainty->absorptivity_sigma;
  }
  Eigen::VectorXd rho = Eigen::VectorXd::Zero(n);
  for (const OpticalSet& set : c.optical_sets)
    if (!set.own_specular)  // a set with networks of its own has its own decomposition
      rho = rho.cwiseMax((1.0 + margin_e - set.emissivity.array()).matrix())
                .cwiseMax((1.0 + margin_a - set.absorptivity.array()).matrix());
  return rho.cwiseMin(1.0);
}

// A decomposition on rank 0, broadcast to the others (who time their wait).
solver::EigenPairs decomposeShared(const solver::Network& net, const Eigen::VectorXd& reflectance,
                                   const std::vector<Eigen::VectorXd>& emissivities,
                                   const solver::SolverSettings& settings, StageTimings& timings) {
  solver::EigenPairs pairs;
  if (!net.share().whole()) return decomposeNetwork(net, reflectance, emissivities, settings, timings);  // every rank its part of each product
  if (cluster::rank() == 0) {
    pairs = decomposeNetwork(net, reflectance, emissivities, settings, timings);
    shareEigenPairs(pairs);
  } else {
    StageTimer waiting(timings, Stage::Eigendecomposition);
    shareEigenPairs(pairs);
  }
  return pairs;
}

// The one decomposition that serves every optical set with the case's ρs and τ.
solver::EigenPairs decomposeOnce(const solver::Network& net, const GeometryCase& c,
                                 const solver::SolverSettings& settings, StageTimings& timings) {
  std::vector<Eigen::VectorXd> emissivities;
  for (const OpticalSet& set : c.optical_sets)
    if (!set.own_specular) emissivities.push_back(set.emissivity);
  return decomposeShared(net, largestReflectance(c), emissivities, settings, timings);
}

// The network's areas in a band: A κ, or A where κ = 0 (a pure mirror: its row and column
// are empty, any positive area serves).
Eigen::VectorXd bandArea(const Eigen::VectorXd& area, const Eigen::VectorXd& kappa) {
  Eigen::VectorXd out = area;
  for (Eigen::Index i = 0; i < area.size(); ++i)
    if (kappa[i] > 0) out[i] *= kappa[i];
  return out;
}

// The rows that see a surface redirecting in either band (or are one: a pure mirror's row
// is replaced by F̃_space = 1): these are traced, the others keep the diffuse F.
std::vector<char> specularRows(const geometry::SpecularBand& ir, const geometry::SpecularBand& solar,
                               const geometry::ViewFactorEstimate& diffuse) {
  const Eigen::Index n = ir.specular.size();
  const auto redirects = [&](Eigen::Index j) {
    return ir.redirects(static_cast<int>(j)) || solar.redirects(static_cast<int>(j));
  };
  std::vector<char> rows(static_cast<size_t>(n), 0);
  for (Eigen::Index i = 0; i < diffuse.view_factors.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(diffuse.view_factors, i); it; ++it)
      if (it.value() > 0 && (redirects(it.col()) || redirects(i))) rows[static_cast<size_t>(i)] = 1;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (redirects(i)) rows[static_cast<size_t>(i)] = 1;  // its own row: what leaves it meets others' optics
    if (ir.kappa()[i] <= 0 || solar.kappa()[i] <= 0) rows[static_cast<size_t>(i)] = 1;
  }
  // Rows seeing a redirector that saw nothing in return (F_ji > 0, F_ij = 0 by sampling).
  for (Eigen::Index i = 0; i < diffuse.view_factors.outerSize(); ++i)
    if (redirects(i))
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(diffuse.view_factors, i); it; ++it)
        rows[static_cast<size_t>(it.col())] = 1;
  return rows;
}

// One band's F̃ = E^s κ: the rows seeing a specular or transmissive surface traced with the
// band's optics, the rest as computed; then the reciprocity/closure correction with Ã = A κ.
geometry::ReciprocityCorrection specularBand(const GeometryCase& c, const geometry::RayCaster& caster,
                                             const geometry::ViewFactorEstimate& diffuse,
                                             const geometry::SpecularBand& band, const std::vector<char>& rows,
                                             const Eigen::VectorXd& area, Eigen::VectorXd rays, GeometryRunResult& r,
                                             geometry::ViewFactorEstimate* kept) {
  geometry::ViewFactorOptions opt = c.view_factors.monte_carlo;
  opt.cast_rows = rows;
  const geometry::ViewFactorResult traced = geometry::traceSpecularRows(caster, band, opt);
  r.specular_rays += traced.total_rays;
  for (char row : rows) r.specular_rows += row;
  const Eigen::VectorXd kappa = band.kappa();
  for (Eigen::Index i = 0; i < rays.size(); ++i)
    if (rows[static_cast<size_t>(i)]) rays[i] = kappa[i] > 0 ? double(traced.rays[static_cast<size_t>(i)]) : 1e15;
  const geometry::ViewFactorEstimate merged = geometry::withSampledRows(diffuse, traced, rows);
  if (kept) *kept = merged;
  return geometry::enforceReciprocity(bandArea(area, kappa), merged, rays);
}

// F before any specular trace and each row's ray count (its variance weight).
struct DiffuseStage {
  geometry::ViewFactorEstimate estimate;
  Eigen::VectorXd rays;
};

// What the view-factor stage did, for the progress stream.
void printViewFactorStage(const GeometryCase& c, const GeometryRunResult& r, std::ostream& progress) {
  progress << "radnet: view factors (" << toString(c.view_factors.method) << "): ";
  if (r.exact)
    progress << r.exact->pairs_unoccluded << " unoccluded and " << r.exact->pairs_occluded
             << " occluded patch pairs exact (" << r.exact->pairs_by_quadrature << " by point rules, "
             << r.exact->seconds << " s), " << r.exact->sampled_rows << " rows left to rays, ";
  progress << r.total_rays << " rays"
           << (r.rays_per_second > 0 ? " (" + std::to_string(static_cast<long long>(r.rays_per_second)) + " rays/s)"
                                     : "")
           << ", reciprocity/closure correction moved F by at most " << r.correction.max_change << " ("
           << r.correction.max_change_sigma << " σ)\n";
  if (c.hasSpecular())
    progress << "radnet: specular/transmissive surfaces: " << r.specular_rows << " row(s) traced with specular "
             << "reflection and transmission (" << r.specular_rays << " rays, "
             << (r.solar_correction ? "IR and solar bands apart" : "one traced network for both bands") << ")\n";
}

// The correction with the raw estimate written out as soon as it is final, its (n, n)
// datasets as the network will be held (from the corrected F's entries), the time the
// output's, not the stage's: laid over the raw F once that is written (the exact method's
// symmetric pattern), else beside it and the raw F written then.
geometry::ReciprocityCorrection correctWritingRaw(const GeometryCase& c, const Eigen::VectorXd& area,
                                                  geometry::ViewFactorEstimate& estimate, const Eigen::VectorXd& rays,
                                                  const RawEstimateWriter& write_raw, StageTimer& timer,
                                                  GeometryRunResult& r) {
  const auto n = static_cast<int>(area.size());
  auto writeRaw = [&](long long corrected_nonzeros) {
    const auto t0 = std::chrono::steady_clock::now();
    write_raw(estimate, c.output.denseMatrices(n, !solver::policy::storeSparse(corrected_nonzeros, n)));
    // σ on F's pattern goes with the raw F's pattern: its rows' largest entries read now.
    if (estimate.errors_on_pattern || estimate.upper_exchange) r.row_stderr_max = geometry::rowLargestErrors(estimate);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    timer.exclude(seconds);
    r.raw_estimate_write_seconds += seconds;
    r.raw_estimate_written = true;
  };
  if (std::optional<geometry::ReciprocityCorrection> in_place =
          geometry::enforceReciprocityInPlace(area, estimate, rays, writeRaw))
    return std::move(*in_place);
  geometry::expandErrors(estimate);
  geometry::ReciprocityCorrection beside = geometry::enforceReciprocity(area, estimate, rays);
  writeRaw(beside.view_factors.nonZeros());
  return beside;
}

// F by ray casting or the exact method, then the variance-weighted reciprocity and
// closure correction (docs/geometry.md); with specular or transmissive surfaces, F̃ per band.
void viewFactorStage(const GeometryCase& c, const geometry::RayCaster& caster, const Eigen::VectorXd& area,
                     GeometryRunResult& r, bool show_progress, std::ostream& progress, DiffuseStage* diffuse,
                     const RawEstimateWriter& write_raw) {
  const Eigen::Index n = area.size();
  StageTimer timer(r.timings, Stage::ViewFactors);
  Eigen::VectorXd rays(n);
  geometry::ViewFactorEstimate estimate;
  const bool shared = sharesRows(c);
  // The raw estimate written early: not with shared rows (their holders join each block of
  // the file at the end), specular bands or a diffuse F kept for other networks (they read
  // the raw F again).
  const bool early = write_raw && !shared && !c.hasSpecular() && !diffuse;
  if (c.view_factors.method == ViewFactorMethod::MonteCarlo) {
    geometry::ViewFactorResult vf = castRays(c, caster, {}, show_progress, progress, shared);
    for (Eigen::Index i = 0; i < n; ++i) rays[i] = double(vf.rays[static_cast<size_t>(i)]);
    r.total_rays = vf.total_rays;
    r.rays_per_second = vf.seconds > 0 ? double(vf.total_rays) / vf.seconds : 0.0;
    moveEstimate(vf, estimate);
  } else {
    // σ on F's pattern when it is read only while that pattern stands (written with the raw F).
    exactStage(c, caster, r, rays, show_progress, progress, estimate, shared, early && !c.readsViewFactorErrors());
  }
  if (diffuse) *diffuse = {estimate, rays};  // what an optical set's own networks start from
  if (c.hasSpecular()) {
    const std::vector<char> rows = specularRows(c.specular_ir, c.specular_solar, estimate);
    if (c.solarSpecularDiffers())
      r.solar_correction = specularBand(c, caster, estimate, c.specular_solar, rows, area, rays, r, nullptr);
    geometry::ViewFactorEstimate traced;
    r.correction = specularBand(c, caster, estimate, c.specular_ir, rows, area, rays, r, &traced);
    estimate = traced;
  } else if (shared) {
    r.correction = geometry::enforceReciprocityOnRows(area, estimate, rays, clusterRowShare());
  } else if (early) {
    r.correction = correctWritingRaw(c, area, estimate, rays, write_raw, timer, r);
  } else {
    r.correction = geometry::enforceReciprocity(area, estimate, rays);
  }
  if (r.raw_estimate_written)
    Eigen::SparseMatrix<double, Eigen::RowMajor>().swap(estimate.view_factors);
  else
    r.raw_view_factors.swap(estimate.view_factors);
  r.view_factor_stderr.swap(estimate.standard_error);
  if (r.row_stderr_max.size() == 0)  // else read with the raw F (σ on its pattern)
    r.row_stderr_max = rowLargestStderr(r.view_factor_stderr, shared ? clusterRowShare() : solver::RowShare());
  if (r.raw_estimate_written && !c.readsViewFactorErrors()) solver::SparseRowMatrix().swap(r.view_factor_stderr);
  // What leaves to space or to inactive sides is uncertain too (it sets the GR to space).
  r.lost_view_factor_stderr = (estimate.space_error.array().square() + estimate.blocked_error.array().square()).sqrt();
  solver::releaseFreedMemory();
  timer.stop();
  printViewFactorStage(c, r, progress);
}

// An optical set that changes ρs or τ: its own F̃ per band, traced from the diffuse F with
// its optics (a set that redirects nothing keeps the diffuse F), on its own Ã = A κ
// (docs/solver.md, "Optical sets that change ρs or τ").
std::shared_ptr<OwnOpticsNetwork> ownOpticsNetwork(const GeometryCase& c, const geometry::RayCaster& caster,
                                                         const Eigen::VectorXd& area, const DiffuseStage& diffuse,
                                                   const OpticalSet& set, GeometryRunResult& r) {
  auto own = std::make_shared<OwnOpticsNetwork>();
  RadiativeNetwork& net = own->radiative;
  geometry::ViewFactorEstimate estimate = diffuse.estimate;
  if (set.specular_ir.empty()) {
    net.network = buildNetwork(c, area, geometry::enforceReciprocity(area, estimate, diffuse.rays));
  } else {
    const std::vector<char> rows = specularRows(set.specular_ir, set.specular_solar, diffuse.estimate);
    const bool bands_differ = !set.specular_ir.sameAs(set.specular_solar);
    net.kappa_ir = set.specular_ir.kappa();
    net.kappa_solar = set.specular_solar.kappa();
    if (bands_differ)
      net.solar_network = buildNetwork(
          c, bandArea(area, net.kappa_solar),
          specularBand(c, caster, diffuse.estimate, set.specular_solar, rows, area, diffuse.rays, r, nullptr));
    net.network = buildNetwork(
        c, bandArea(area, net.kappa_ir),
        specularBand(c, caster, diffuse.estimate, set.specular_ir, rows, area, diffuse.rays, r, &estimate));
    net.surface_area = area;
    net.solar_specular = set.specular_solar;
    net.ir_specular = set.specular_ir;
  }
  own->area = net.network->area();
  own->view_factor_stderr = estimate.standard_error;
  own->lost_view_factor_stderr =
      (estimate.space_error.array().square() + estimate.blocked_error.array().square()).sqrt();
  return own;
}

// Every optical set's own networks (null: the set is solved on the case's), each with its
// own decomposition: its G̃ is not the case's.
std::vector<std::shared_ptr<const OwnOpticsNetwork>> ownOpticsNetworks(const GeometryCase& c,
                                                                       const geometry::RayCaster& caster,
                                                                       const Eigen::VectorXd& area,
                                                                       const DiffuseStage& diffuse,
                                                                       GeometryRunResult& r, std::ostream& progress) {
  std::vector<std::shared_ptr<const OwnOpticsNetwork>> out(c.optical_sets.size());
  for (size_t k = 0; k < c.optical_sets.size(); ++k) {
    const OpticalSet& set = c.optical_sets[k];
    if (!set.own_specular) continue;
    StageTimer timer(r.timings, Stage::ViewFactors);
    const std::shared_ptr<OwnOpticsNetwork> own = ownOpticsNetwork(c, caster, area, diffuse, set, r);
    timer.stop();
    const Eigen::VectorXd one = Eigen::VectorXd::Ones(set.emissivity.size());
    own->radiative.pairs = decomposeShared(*own->radiative.network, (one - set.emissivity).cwiseMax(one - set.absorptivity),
                                           {set.emissivity}, r.solver, r.timings);
    for (const std::string& w : decompositionWarnings(own->radiative.pairs, r.solver))
      progress << "radnet: warning: optical set '" << set.name << "': " << w << "\n";
    progress << "radnet: optical set '" << set.name << "' changes ρs or τ: its own traced network and "
             << "eigendecomposition (rank " << own->radiative.pairs.rank() << ")\n";
    out[k] = own;
  }
  return out;
}

// Nodes a thermal engineer must hear about by name: one that absorbs nothing at any position
// although it sees space (its fronts face inward, or it hides inside a closed part), and one
// whose temperature falls below kColdestLikelyK (nothing heats it). Boundary nodes (a fixed
// temperature the user gave) are left out.
constexpr double kSeesSpace = 1e-3;        // F_space above which a node sees the sky, –
constexpr double kColdestLikelyK = 10.0;   // below this no spacecraft node is meant to be, K

void suspiciousNodeWarnings(const GeometryCase& c, const GeometryRunResult& r, std::ostream& progress) {
  if (r.sweep && r.radiative.network) {
    const Eigen::VectorXd& f_space = r.radiative.network->spaceViewFactor();
    const std::vector<std::string>& names = r.radiative.network->names();
    for (Eigen::Index i = 0; i < r.sweep->absorbed_total.rows() && i < f_space.size(); ++i)
      if (f_space[i] > kSeesSpace && std::max(c.absorptivity[i], c.emissivity[i]) > 0.0 &&
          !(r.sweep->absorbed_total.row(i).maxCoeff() > 0.0))
        progress << "radnet: warning: node '" << names[static_cast<size_t>(i)]
                 << "' absorbs nothing at any position although it sees space (F_space = " << f_space[i]
                 << "): unless it is meant to stay dark, do its fronts face inward (a mesh's `flip: true`)?\n";
  }
  if (!r.thermal || !c.thermal) return;
  const Eigen::MatrixXd& t = r.thermal->temperature();
  const Eigen::VectorXd& fixed = c.thermal->fixed_temperature;
  for (Eigen::Index i = 0; i < t.rows(); ++i) {
    const double lowest = t.row(i).minCoeff();
    if (lowest < kColdestLikelyK && !(i < fixed.size() && std::isfinite(fixed[i])))
      progress << "radnet: warning: node '" << r.thermal->node_names[static_cast<size_t>(i)] << "' falls to "
               << lowest << " K: nothing heats it (no load reaches it, no conductor joins it?)\n";
  }
}

// The network from the corrected F; with specular surfaces on the band's areas A κ
// (docs/solver.md), and the solar band's own when its optics differ. Returns the areas.
Eigen::VectorXd networkStage(const GeometryCase& c, const Eigen::VectorXd& area, GeometryRunResult& r) {
  StageTimer timer(r.timings, Stage::Network);
  Eigen::VectorXd network_area = area;
  if (c.hasSpecular()) {
    r.radiative.surface_area = area;
    r.radiative.kappa_ir = c.specular_ir.kappa();
    r.radiative.kappa_solar = c.specular_solar.kappa();
    r.radiative.solar_specular = c.specular_solar;
    r.radiative.ir_specular = c.specular_ir;
    network_area = bandArea(area, r.radiative.kappa_ir);
    if (r.solar_correction)
      r.radiative.solar_network = buildNetwork(c, bandArea(area, r.radiative.kappa_solar), *r.solar_correction);
  }
  r.radiative.network = buildNetwork(c, network_area, r.correction);
  solver::releaseFreedMemory();  // the correction's working memory (0.25 GB kept on the 6,144-node room)
  return network_area;
}

}  // namespace

GeometryRunResult runGeometryCase(const GeometryCase& c, bool show_progress, std::ostream& progress,
                                  const RawEstimateWriter& write_raw) {
  GeometryRunResult r;
  const geometry::Scene& scene = c.scene;
  const int n = static_cast<int>(scene.nodes().size());
  for (const auto& w : scene.warnings()) progress << "radnet: warning: " << w << "\n";
  for (const auto& w : c.warnings) progress << "radnet: warning: " << w << "\n";
  progress << "radnet: scene of " << scene.faces().size() << " triangles, " << n << " nodes\n";
  const Eigen::VectorXi front = scene.frontNodes(), back = scene.backNodes();
  r.triangle_node = front.binaryExpr(back, [](int f, int b) { return f >= 0 ? f : b; });
  StageTimer t_tree(r.timings, Stage::AabbTree);
  const geometry::RayCaster caster(scene);
  t_tree.stop();

  Eigen::VectorXd area(n);
  for (int i = 0; i < n; ++i) area[i] = scene.nodes()[static_cast<size_t>(i)].area_m2;
  const bool own_optics = std::any_of(c.optical_sets.begin(), c.optical_sets.end(),
                                      [](const OpticalSet& set) { return set.own_specular; });
  const bool turning = !c.articulation.drives.empty();
  DiffuseStage diffuse;
  viewFactorStage(c, caster, area, r, show_progress, progress, own_optics || turning ? &diffuse : nullptr, write_raw);
  std::optional<ArticulatedBase> turning_base;
  if (turning) turning_base = turningBase(c, caster, area, diffuse.estimate, diffuse.rays, r, progress);
  const Eigen::VectorXd network_area = networkStage(c, area, r);

  // One decomposition serves every optical set and sample: its rank rule takes the largest
  // reflectance any of them may give each node.
  r.solver = budgetedSolverSettings(c.solver, r.row_stderr_max.size() ? r.row_stderr_max.maxCoeff() : 0.0);
  r.solver.exchange_from_pairs = turning;  // one GR per configuration: from the pairs, not O(n³) each
  r.radiative.pairs = decomposeOnce(*r.radiative.network, c, r.solver, r.timings);
  for (const std::string& w : decompositionWarnings(r.radiative.pairs, r.solver))
    progress << "radnet: warning: " << w << "\n";
  r.radiative.exchange = exchangeFactors(r.radiative, c.emissivity, r.solver, r.timings);
  DesignContext ctx{c, caster, r.radiative, r.solver, r.view_factor_stderr, r.lost_view_factor_stderr, network_area};
  if (own_optics) ctx.own_networks = ownOpticsNetworks(c, caster, area, diffuse, r, progress);
  const std::unique_ptr<Articulated> articulated =
      turning ? std::make_unique<Articulated>(c, std::move(*turning_base), caster, r.radiative, r.view_factor_stderr,
                                              r.lost_view_factor_stderr, r.solver)
              : nullptr;
  ctx.articulated = articulated.get();
  std::vector<CaseRun> runs;
  runDesignCases(ctx, r, runs, show_progress, progress);
  if (!c.articulation.empty()) r.articulation = articulationResult(c, articulated.get(), r.timings);
  suspiciousNodeWarnings(c, r, progress);
  if (c.optical_uncertainty) {
    StageTimer t_opt(r.timings, Stage::OpticalUncertainty);
    r.optical_uncertainty = sampleOpticalUncertainty(ctx, runs, r.cases.band_cores, show_progress, progress);
  }
  // Counted, not asserted: a stage that decomposed G again would show here.
  r.cases.eigendecompositions = r.timings.count(Stage::Eigendecomposition);
  slowestRankTimings(r.timings);
  return r;
}

}  // namespace radnet::cases
