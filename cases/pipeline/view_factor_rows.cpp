#include "cases/pipeline/view_factor_rows.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/progress.hpp"
#include "solver/radiative/policy.hpp"

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
                                   std::vector<char> rows, bool show_progress, std::ostream& progress) {
  geometry::ViewFactorOptions opt = c.view_factors.monte_carlo;
  const bool some = !rows.empty();
  opt.cast_rows = myRows(std::move(rows), caster.scene().nodes().size());
  if (show_progress) opt.progress = progressBar(progress, some ? "view factors (rays)" : "view factors", "nodes");
  geometry::ViewFactorResult vf = geometry::computeViewFactors(caster, opt);
  joinViewFactorRows(vf);
  return vf;
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

}  // namespace radnet::cases
