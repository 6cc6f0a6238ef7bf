#include "solver/radiative/policy.hpp"

#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/rank_probe.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace radnet::solver::policy {

EigenMethod eigenMethod(EigenMethod requested, int n, int rank) {
  if (requested != EigenMethod::Auto) return requested;
  const bool most_pairs = rank > 0 && kDenseEigenRankDivisor * rank > n;
  return n <= kDenseEigenMaxNodes || most_pairs ? EigenMethod::Dense : EigenMethod::Lanczos;
}

bool storeSparse(long long nonzeros, int n) { return double(nonzeros) / (double(n) * n) < kSparseStorageMaxDensity; }

BandSolveCost bandSolveCost(const Network& net, int rank, Eigen::Index columns, double start_residual,
                            double tolerance) {
  BandSolveCost cost;
  const double n = net.size(), p = double(columns);
  // Measured: 5.2e-3 → 4.2e-4 in 1 iteration, 2.6e-2 → 4.2e-4 in 2, 5e-2 → 1e-10 in 12
  // (docs/solver-satellite-benchmark.md, docs/solver-benchmark.md); √r₀ per iteration
  // predicts 1, 3 and 14.
  const double contraction = std::clamp(std::sqrt(start_residual), 1e-3, 0.9);
  cost.refine_iterations =
      start_residual <= tolerance ? 0 : int(std::ceil(std::log(tolerance / start_residual) / std::log(contraction)));
  const double product_flops = net.isSparse() ? 2.0 * double(net.conductanceNonZeros()) : 2.0 * n * n;
  const double product_rate = net.isSparse() ? kSparseFlopsPerSecond : kDenseFlopsPerSecond;
  const double per_iteration = p * (product_flops / product_rate + (4.0 * n * rank + 12.0 * n) / kSparseFlopsPerSecond);
  cost.refine_s = cost.refine_iterations * per_iteration;
  cost.direct_s = net.size() > kDenseBandSolveMaxNodes
                      ? std::numeric_limits<double>::infinity()
                      : (2.0 / 3.0 * n * n * n + 2.0 * n * n * p) / kDenseFlopsPerSecond;
  return cost;
}

bool exchangeFromPairs(int n, const SolverSettings& settings) {
  return settings.exchange_from_pairs || !(settings.refineEnabled() && n <= kDenseExchangeMaxNodes);
}

// Pairs measured on the probes (rank_probe.hpp): band residual, and GR error when GR comes
// from the pairs and the case has emissivities.
EigenPairs measuredPairs(const Network& net, EigenPairs pairs, const Eigen::VectorXd& max_reflectance,
                         const SolverSettings& settings, const std::vector<Eigen::VectorXd>& emissivities) {
  if (pairs.status != Status::Converged || pairs.rank() == 0) return pairs;
  RankTargets targets;
  targets.reflectance = max_reflectance;
  const bool exchange = exchangeFromPairs(net.size(), settings) && !emissivities.empty();
  targets.exchange_error = exchange ? 1.0 : 0.0;  // any positive value: measure it
  targets.emissivities = emissivities;
  RankProbe probe(net, targets);
  const RankMeasure kept = probe.measure(pairs, pairs.rank());
  pairs.probe_residual = kept.band_residual;
  if (exchange) pairs.probe_exchange_error = kept.exchange_error;
  return pairs;
}

EigenPairs decomposeForBands(const Network& net, const Eigen::VectorXd& max_reflectance,
                             const SolverSettings& settings, const std::vector<Eigen::VectorXd>& emissivities) {
  EigenRequest req;
  req.rank = settings.rank;
  req.tolerance = settings.tolerance;
  req.max_s = std::max(max_reflectance.cwiseQuotient(net.area()).maxCoeff(), 1e-300);
  req.max_rank = settings.max_rank;
  req.method = settings.method;
  if (settings.rank > 0)  // kept as asked, measured all the same
    return measuredPairs(net, decomposeConductance(net, req), max_reflectance, settings, emissivities);
  // The rank from the tolerance, measured (rank_probe.hpp): the refined band solves need
  // only a good start, the rank-k answer kept or GR from the pairs need the tolerance.
  RankTargets targets;
  targets.reflectance = max_reflectance;
  targets.band_residual =
      settings.refineEnabled() ? std::max(kRefinedStartResidual, settings.tolerance) : settings.tolerance;
  targets.exchange_error = exchangeFromPairs(net.size(), settings) ? settings.tolerance : 0.0;
  targets.emissivities = emissivities;
  targets.exchange_fallback = net.size() <= kDenseBandSolveMaxNodes;
  targets.band_refined = settings.refineEnabled();
  RankProbe probe(net, targets);
  req.accept = [&probe](const EigenPairs& found) { return probe(found); };
  req.next = [&probe](int nev) { return probe.nextRank(nev); };
  EigenPairs pairs = decomposeConductance(net, req);
  if (pairs.status != Status::Converged || pairs.rank() == 0) return pairs;
  if (pairs.rank_rule == "a posteriori") pairs.rank_rule = probe.rule();
  const RankMeasure kept = probe.measure(pairs, pairs.rank());
  pairs.probe_residual = kept.band_residual;
  if (targets.exchange_error > 0) pairs.probe_exchange_error = kept.exchange_error;
  return pairs;
}

ExchangeFactors exchangeFactors(const Network& net, const EigenPairs& pairs, const Eigen::VectorXd& emissivity,
                                const SolverSettings& settings) {
  // Dense LU also when the pairs missed the tolerance on the probes' GR x and the network is
  // small enough for it (a closed room's flat spectrum).
  const bool pairs_short = settings.rank == 0 && pairs.probe_exchange_error > settings.tolerance &&
                           net.size() <= kDenseBandSolveMaxNodes;  // an explicit rank is the user's choice
  if (!exchangeFromPairs(net.size(), settings) || pairs_short) return exchangeFactorsDense(net, emissivity);
  const LowRankBandSolver ir(net, pairs, Eigen::VectorXd::Ones(net.size()) - emissivity);
  return exchangeFactorsLowRank(net, ir, emissivity);
}

}  // namespace radnet::solver::policy
