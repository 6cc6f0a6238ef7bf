#include "cases/pipeline/network_run.hpp"

#include "cases/config/errors.hpp"
#include "cases/pipeline/radiative_network.hpp"
#include "cases/pipeline/thermal_run.hpp"

#include <ostream>

namespace radnet::cases {

NetworkRunResult runNetworkCase(const NetworkCase& c, std::ostream& progress) {
  NetworkRunResult r;
  StageTimer t_network(r.timings, Stage::Network);
  r.radiative.network = std::make_unique<solver::Network>(c.buildNetwork());
  const solver::Network& net = *r.radiative.network;
  t_network.stop();
  progress << "radnet: network of " << net.size() << " nodes (" << (net.isSparse() ? "sparse" : "dense")
           << "), reciprocity correction moved a view factor by at most " << net.reciprocity().max_view_factor_change
           << "\n";

  // One eigendecomposition serves both bands.
  Eigen::VectorXd rho_max = c.reflectance;
  if (c.emissivity) rho_max = rho_max.cwiseMax(Eigen::VectorXd::Ones(net.size()) - *c.emissivity);
  std::vector<Eigen::VectorXd> emissivities;
  if (c.emissivity) emissivities.push_back(*c.emissivity);
  r.radiative.pairs = decomposeNetwork(net, rho_max, emissivities, c.solver, r.timings);
  const solver::EigenPairs& pairs = r.radiative.pairs;
  for (const std::string& w : decompositionWarnings(pairs, c.solver)) progress << "radnet: warning: " << w << "\n";
  progress << "radnet: " << pairs.rank() << " eigenpairs (" << solver::toString(pairs.method) << ")";
  if (pairs.rank() > 0) progress << ", largest |λ| " << std::abs(pairs.values[0]) << " m²";
  else progress << ": no exchange between the nodes (G = 0)";
  progress << ", largest dropped ≤ " << pairs.dropped_bound << " m²\n";

  StageTimer t_band(r.timings, Stage::BandSolves);
  const solver::LowRankBandSolver band(net, r.radiative.pairs, c.reflectance);
  r.solution = band.solve(c.initial_exitance, c.solver.refineTolerance());
  t_band.stop();
  if (r.solution.status != solver::Status::Converged)
    throw NumericalError(std::string("band solve ") + solver::toString(r.solution.status) + ": " + r.solution.message);

  if (c.emissivity) r.radiative.exchange = exchangeFactors(r.radiative, *c.emissivity, c.solver, r.timings);
  if (c.thermal) r.thermal = runThermal(*c.thermal, *r.radiative.exchange, nullptr, r.timings, progress);
  return r;
}

ImportRunResult runImportedCase(const ImportedCase& c, std::ostream& progress) {
  ImportRunResult r;
  progress << "radnet: imported " << c.thermal.nodeCount() << " nodes, " << c.thermal.conductors.size() / 2 << " GL and "
           << c.thermal.radiative_couplings.size() / 2 << " GR from " << c.source << "\n";
  solver::ExchangeFactors none;  // the file's GR are user couplings: no radiative node of radnet's
  none.gr.resize(0, 0), none.gr_space.resize(0);
  r.thermal = runThermal(c.thermal, none, nullptr, r.timings, progress);
  for (double& t : r.thermal.times_s) t += c.time_offset_s;  // the file's own times
  return r;
}

}  // namespace radnet::cases
