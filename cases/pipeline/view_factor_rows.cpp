#include "cases/pipeline/view_factor_rows.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/config/work_estimate.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/progress.hpp"
#include "cases/pipeline/shared_rows.hpp"
#include "solver/radiative/policy.hpp"
#include "geometry/exact/view_factors.hpp"


#include <algorithm>
#include <ostream>

namespace radnet::cases {
namespace {

// The rows to cast (empty: all) dealt round robin over the MPI ranks: this rank's share.
std::vector<char> myRows(std::vector<char> rows, std::size_t n) {
  if (!cluster::distributed()) return rows;
  if (rows.empty()) rows.assign(n, 1);
  long long dealt = 0;
  for (char& row : rows)
    if (row) row = cluster::owns(dealt++);
  return rows;
}

}  // namespace

geometry::ViewFactorResult castRays(const GeometryCase& c, const geometry::RayCaster& caster,
                                   std::vector<char> rows, bool show_progress, std::ostream& progress, bool shared) {
  geometry::ViewFactorOptions opt = c.view_factors.monte_carlo;
  const bool some = !rows.empty();
  const std::size_t n = caster.scene().nodes().size();
  if (shared) {  // the rows this rank holds (RowShare::holds)
    if (rows.empty()) rows.assign(n, 1);
    const solver::RowShare share = clusterRowShare();
    for (std::size_t i = 0; i < n; ++i) rows[i] = rows[i] && share.holds(static_cast<Eigen::Index>(i));
    opt.cast_rows = std::move(rows);
  } else {
    opt.cast_rows = myRows(std::move(rows), n);
  }
  if (show_progress) opt.progress = progressBar(progress, some ? "view factors (rays)" : "view factors", "nodes");
  geometry::ViewFactorResult vf = geometry::computeViewFactors(caster, opt);
  if (shared) joinHeldRowVectors(vf);
  else joinViewFactorRows(vf);
  return vf;
}

// The network from the corrected F, stored sparse or dense by the solver policy.
std::unique_ptr<solver::Network> buildNetwork(const GeometryCase& c, const Eigen::VectorXd& area,
                                              geometry::ReciprocityCorrection& correction) {
  const int n = static_cast<int>(area.size());
  const auto tol = solver::policy::kCorrectedNetworkTolerances;
  if (correction.transposed.rows() > 0) {  // shared rows (shared_rows.hpp)
    auto net = std::make_unique<solver::Network>(c.node_names, area, correction.view_factors, correction.transposed,
                                                 correction.blocked, tol, clusterRowShare());
    Eigen::SparseMatrix<double, Eigen::RowMajor>().swap(correction.view_factors);
    Eigen::SparseMatrix<double, Eigen::RowMajor>().swap(correction.transposed);
    return net;
  }
  if (correction.exchange_upper.rows() > 0) {  // exchange areas held once per pair (the exact method's)
    Eigen::SparseMatrix<double, Eigen::RowMajor> upper;
    upper.swap(correction.exchange_upper);
    if (!solver::policy::storeSparse(geometry::fullNonZeros(upper), n)) {
      // G is formed in the storage of F laid out dense (as below), straight from the pairs.
      Eigen::MatrixXd dense = geometry::denseViewFactorsFromUpper(upper, area);
      Eigen::SparseMatrix<double, Eigen::RowMajor>().swap(upper);
      return std::make_unique<solver::Network>(c.node_names, area, std::move(dense), correction.blocked, tol);
    }
    correction.view_factors = geometry::viewFactorsFromUpper(upper, area);
  }
  // Nothing reads the correction's F after the network: swapped out once copied (an
  // assignment would keep Eigen's storage allocated).
  if (solver::policy::storeSparse(correction.view_factors.nonZeros(), n)) {
    const Eigen::SparseMatrix<double> f = correction.view_factors;  // the column-major form the network takes
    Eigen::SparseMatrix<double, Eigen::RowMajor>().swap(correction.view_factors);
    return std::make_unique<solver::Network>(c.node_names, area, f, correction.blocked, tol);
  }
  // Dense: F laid out once, and G formed in its storage (the 6,144-node room: one n × n
  // matrix beside the sparse F, not three).
  Eigen::MatrixXd dense = correction.view_factors;
  Eigen::SparseMatrix<double, Eigen::RowMajor>().swap(correction.view_factors);
  return std::make_unique<solver::Network>(c.node_names, area, std::move(dense), correction.blocked, tol);
}

// Moves F, σ and the per-node vectors of `from` into `to`. Eigen 3.4's sparse matrices
// have no move constructor (std::move copies them): swapped instead, since at 6,144 nodes F
// and σ are 0.75 GB and a copy costs 1–1.5 s of fresh pages here.
void moveEstimate(geometry::ViewFactorEstimate& from, geometry::ViewFactorEstimate& to) {
  to.view_factors.swap(from.view_factors);
  to.standard_error.swap(from.standard_error);
  to.error_on_pattern.swap(from.error_on_pattern);
  std::swap(to.errors_on_pattern, from.errors_on_pattern);
  to.exchange_upper.swap(from.exchange_upper);
  to.exchange_error_upper.swap(from.exchange_error_upper);
  to.upper_area.swap(from.upper_area);
  std::swap(to.upper_exchange, from.upper_exchange);
  to.space.swap(from.space);
  to.space_error.swap(from.space_error);
  to.blocked.swap(from.blocked);
  to.blocked_error.swap(from.blocked_error);
}

// Auto's cap on F's entries from integrated pairs (cases/config/work_estimate.hpp), from the
// least memory of any rank: every rank must plan the same rows.
std::int64_t pairEntriesCap(const GeometryCase& c) {
  double memory = memoryLimit().bytes;
  if (cluster::distributed()) {
    const std::vector<double> all = cluster::gatherAll(std::vector<double>{memory > 0 ? memory : -1.0});
    for (double m : all) memory = m > 0 && (memory <= 0 || m < memory) ? m : memory;
  }
  return pairEntriesCap(c, memory);
}

geometry::ExactOptions plannedExactOptions(const GeometryCase& c) {
  geometry::ExactOptions opt = c.view_factors.exact;
  const bool automatic = c.view_factors.method == ViewFactorMethod::Auto;
  opt.max_blockers = !automatic ? -1 : (opt.max_blockers >= 0 ? opt.max_blockers : geometry::kAutoMaxBlockers);
  opt.max_patches = automatic ? geometry::kAutoMaxPatches : -1;
  opt.row_sampling_seconds = automatic ? rowRays(c) * geometry::kSecondsPerRay : 0.0;
  opt.max_entries = -1;
  return opt;
}

// F by the exact method into `estimate`, with the rows it leaves to sampling (auto) cast as rays.
void exactStage(const GeometryCase& c, const geometry::RayCaster& caster, GeometryRunResult& r, Eigen::VectorXd& rays,
                bool show_progress, std::ostream& progress, geometry::ViewFactorEstimate& estimate, bool shared,
                bool errors_on_pattern) {
  geometry::ExactOptions opt = plannedExactOptions(c);
  opt.errors_on_pattern = errors_on_pattern && !shared;
  // Every row integrated: each pair held once, corrected where it lies (correctWritingRaw).
  opt.upper_exchange = opt.errors_on_pattern;
  const bool automatic = c.view_factors.method == ViewFactorMethod::Auto;
  opt.max_entries = automatic ? pairEntriesCap(c) : -1;
  if (show_progress) opt.progress = progressBar(progress, "view factors", "patches");
  if (cluster::distributed()) {  // the pair integrals shared out over the ranks by emitting patch
    opt.part = cluster::rank();
    opt.parts = cluster::size();
    opt.gather = [](const std::vector<double>& mine) { return cluster::gatherAll(mine); };
  }
  geometry::ExactResult ex = geometry::exactViewFactors(c.scene, opt);
  solver::releaseFreedMemory();
  r.exact = ExactViewFactorStats{ex.patches,        ex.pairs_culled, ex.pairs_hidden, ex.pairs_unoccluded,
                                 ex.pairs_occluded, 0,               ex.seconds};
  r.exact->pairs_by_quadrature = ex.pairs_by_quadrature;
  if (automatic) {  // the plan's pairs, and the rows it leaves to rays at the case's rays per node
    r.exact->predicted_seconds = ex.predicted_seconds;
    for (char row : ex.sampled_rows)
      if (row)
        r.exact->predicted_seconds += rowRays(c) * geometry::kSecondsPerRay / ex.threads;
  }
  // The quadrature stops at max_depth: say so when an estimate stayed above its target
  // (the absolute tolerance, or the relative one times the entry).
  const double worst = ex.worst_error, worst_target = ex.worst_error_target;
  if (worst > worst_target * (1 + 1e-9))
    progress << "radnet: warning: exact view factors: an error estimate of " << worst << " exceeds its target "
             << worst_target << " (occluded pairs reached the refinement limit); /network/view_factor_stderr "
             << "has it per entry\n";
  // An exact row's entries are good to the tolerance: that is its variance floor.
  rays.setConstant(1.0 / opt.tolerance);
  moveEstimate(ex, estimate);
  if (shared) keepHeldRows(estimate, clusterRowShare());
  for (char row : ex.sampled_rows) r.exact->sampled_rows += row;
  r.exact->sampled_row_mask = ex.sampled_rows;
  if (ex.rows_for_memory > 0)
    progress << "radnet: view factors: " << ex.rows_for_memory << " row(s) cast as rays instead of integrated: "
             << "their pairs' " << ex.entries_for_memory << " entries of F would not fit in "
             << kPairEntriesMemoryShare * 100 << " % of " << memoryLimit().source << "\n";
  if (r.exact->sampled_rows == 0) return;
  geometry::expandErrors(estimate);  // the sampled rows' σ has a pattern of its own
  const geometry::ViewFactorResult vf = castRays(c, caster, ex.sampled_rows, show_progress, progress, shared);
  for (Eigen::Index i = 0; i < rays.size(); ++i)
    if (ex.sampled_rows[static_cast<size_t>(i)]) rays[i] = double(vf.rays[static_cast<size_t>(i)]);
  r.total_rays = vf.total_rays;
  r.rays_per_second = vf.seconds > 0 ? double(vf.total_rays) / vf.seconds : 0.0;
  geometry::ViewFactorEstimate merged = geometry::withSampledRows(estimate, vf, ex.sampled_rows);
  moveEstimate(merged, estimate);
}

}  // namespace radnet::cases
