#include "solver/policy.hpp"

#include "solver/low_rank_solver.hpp"

#include <algorithm>

namespace radnet::solver::policy {

EigenMethod eigenMethod(EigenMethod requested, int n, int rank) {
  if (requested != EigenMethod::Auto) return requested;
  const bool most_pairs = rank > 0 && kDenseEigenRankDivisor * rank > n;
  return n <= kDenseEigenMaxNodes || most_pairs ? EigenMethod::Dense : EigenMethod::Lanczos;
}

bool storeSparse(long long nonzeros, int n) { return double(nonzeros) / (double(n) * n) < kSparseStorageMaxDensity; }

EigenPairs decomposeForBands(const Network& net, const Eigen::VectorXd& max_reflectance,
                             const SolverSettings& settings) {
  EigenRequest req;
  req.rank = settings.rank;
  req.tolerance = settings.tolerance;
  req.max_s = std::max(max_reflectance.cwiseQuotient(net.area()).maxCoeff(), 1e-300);
  req.max_rank = settings.max_rank;
  req.method = settings.method;
  return decomposeConductance(net, req);
}

ExchangeFactors exchangeFactors(const Network& net, const EigenPairs& pairs, const Eigen::VectorXd& emissivity,
                                const SolverSettings& settings) {
  if (settings.refineEnabled() && net.size() <= kDenseExchangeMaxNodes) return exchangeFactorsDense(net, emissivity);
  const LowRankBandSolver ir(net, pairs, Eigen::VectorXd::Ones(net.size()) - emissivity);
  return exchangeFactorsLowRank(net, ir, emissivity);
}

}  // namespace radnet::solver::policy
