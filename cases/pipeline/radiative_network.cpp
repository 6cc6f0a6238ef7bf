#include "cases/pipeline/radiative_network.hpp"

#include "cases/config/errors.hpp"
#include "cases/config/error_budget.hpp"
#include "solver/radiative/policy.hpp"

#include <sstream>

namespace radnet::cases {

solver::EigenPairs decomposeNetwork(const solver::Network& net, const Eigen::VectorXd& max_reflectance,
                                    const std::vector<Eigen::VectorXd>& emissivities,
                                    const solver::SolverSettings& settings, StageTimings& timings) {
  StageTimer timer(timings, Stage::Eigendecomposition);
  solver::EigenPairs pairs = solver::policy::decomposeForBands(net, max_reflectance, settings, emissivities);
  timer.stop();
  if (pairs.status != solver::Status::Converged)
    throw NumericalError(std::string("eigendecomposition of G ") + solver::toString(pairs.status) + ": " +
                         pairs.message);
  return pairs;
}

std::vector<std::string> decompositionWarnings(const solver::EigenPairs& pairs, const solver::SolverSettings& settings) {
  std::vector<std::string> out;
  if (!pairs.fallback.empty()) out.push_back("eigendecomposition: " + pairs.fallback);
  if (std::string w = rankWarning(pairs, settings); !w.empty()) out.push_back(std::move(w));
  return out;
}

std::string rankWarning(const solver::EigenPairs& pairs, const solver::SolverSettings& settings) {
  if (pairs.rank_rule == "explicit") {
    // Both truncations are in the reported uncertainty, but the budget was not met.
    const double allowed = kSolverShare * settings.accuracy;
    if (!(pairs.probe_exchange_error > allowed)) return "";
    std::ostringstream w;
    w << "solver.rank = " << pairs.rank() << " leaves the exchange factors GR off by up to "
      << pairs.probe_exchange_error << " of a node's own emission on the probes, above the " << allowed
      << " the error budget allows the solver (the temperatures' uncertainty carries it as a bound): drop `rank` "
         "to let the budget choose, or raise it";
    return w.str();
  }
  if (pairs.rank_rule != "rank cap") return "";
  const bool gr_short = pairs.probe_exchange_error > settings.tolerance &&
                        pairs.vectors.rows() > solver::policy::kDenseBandSolveMaxNodes;  // else GR exact (dense)
  const bool band_short = !settings.refineEnabled() && pairs.probe_residual > settings.tolerance;
  if (!gr_short && !band_short) return "";
  std::ostringstream w;
  w << "the eigendecomposition stopped at solver.max_rank = " << settings.max_rank << " pairs with the probes' "
    << (gr_short ? "GR error " + std::to_string(pairs.probe_exchange_error)
                 : "band residual " + std::to_string(pairs.probe_residual))
    << " above the tolerance " << settings.tolerance
    << (gr_short ? " (the temperatures' uncertainty carries it as a bound)"
                 : " (the absorbed powers' uncertainty carries it as its truncation part)")
    << ": raise solver.max_rank, or accept the looser " << (gr_short ? "exchange factors" : "band solves");
  return w.str();
}

solver::ExchangeFactors exchangeFactors(const RadiativeNetwork& radiative, const Eigen::VectorXd& emissivity,
                                        const solver::SolverSettings& settings, StageTimings& timings) {
  StageTimer timer(timings, Stage::ExchangeFactors);
  solver::ExchangeFactors ex =
      solver::policy::exchangeFactors(*radiative.network, radiative.pairs, emissivity, settings);
  timer.stop();
  if (ex.status != solver::Status::Converged)
    throw NumericalError(std::string("exchange factors ") + solver::toString(ex.status) + ": " + ex.message);
  return ex;
}

}  // namespace radnet::cases
