#include "cases/pipeline/radiative_network.hpp"

#include "cases/config/errors.hpp"
#include "solver/policy.hpp"

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
