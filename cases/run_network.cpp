#include "cases/run_network.hpp"

#include "cases/errors.hpp"
#include "cases/hdf5_writer.hpp"
#include "cases/output.hpp"

#include <chrono>
#include <ctime>
#include <iomanip>
#include <ostream>

namespace radnet::cases {
NetworkRunResult runNetworkCase(const NetworkCase& c, std::ostream& progress) {
  NetworkRunResult r;
  StageTimer t_network;
  r.network = std::make_unique<solver::Network>(c.buildNetwork());
  const solver::Network& net = *r.network;
  r.timings_s.emplace_back("network", t_network.seconds());
  progress << "radnet: network of " << net.size() << " nodes (" << (net.isSparse() ? "sparse" : "dense")
           << "), reciprocity correction moved a view factor by at most " << net.reciprocity().max_view_factor_change
           << "\n";

  // One eigendecomposition serves both bands.
  Eigen::VectorXd rho_max = c.reflectance;
  if (c.emissivity) rho_max = rho_max.cwiseMax(Eigen::VectorXd::Ones(net.size()) - *c.emissivity);
  StageTimer t_eigen;
  r.pairs = decomposeForBands(net, rho_max, c.solver.rank, c.solver.tolerance, c.solver.max_rank, c.solver.method);
  r.timings_s.emplace_back("eigendecomposition", t_eigen.seconds());
  if (r.pairs.status != solver::Status::Converged)
    throw NumericalError(std::string("eigendecomposition of G ") + solver::toString(r.pairs.status) + ": " +
                         r.pairs.message);
  progress << "radnet: " << r.pairs.rank() << " eigenpairs (" << solver::toString(r.pairs.method) << "), largest |λ| "
           << std::abs(r.pairs.values[0]) << " m², largest dropped ≤ " << r.pairs.dropped_bound << " m²\n";

  StageTimer t_band;
  const double refine_tol = c.solver.refineEnabled() ? c.solver.tolerance : 0.0;
  solver::LowRankBandSolver band(net, r.pairs, c.reflectance);
  r.solution = band.solve(c.initial_exitance, refine_tol);
  r.timings_s.emplace_back("band solve", t_band.seconds());
  if (r.solution.status != solver::Status::Converged)
    throw NumericalError(std::string("band solve ") + solver::toString(r.solution.status) + ": " +
                         r.solution.message);

  if (c.emissivity) {
    StageTimer t_exchange;
    r.exchange = computeExchangeFactors(net, r.pairs, *c.emissivity, c.solver.refineEnabled(), r.exchange_method);
    r.timings_s.emplace_back("exchange factors", t_exchange.seconds());
  }
  if (c.thermal) {  // steady state with the dissipations and boundary temperatures
    r.thermal = solver::steadyStates(thermalNetwork(*c.thermal, r.exchange->gr, r.exchange->gr_space),
                                     Eigen::MatrixXd::Zero(net.size(), 1), c.thermal->options);
    if (r.thermal->status != solver::Status::Converged)
      throw NumericalError(std::string("temperatures ") + solver::toString(r.thermal->status) + ": " +
                           r.thermal->message);
  }
  return r;
}

void writeNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const std::string& path) {
  const solver::Network& net = *r.network;
  Hdf5Writer h5(path);
  writeMeta(h5, c.name, c.yaml_text);
  writeNetwork(h5, net);
  h5.writeVector("/nodes/reflectance", c.reflectance, "1");
  h5.writeVector("/nodes/initial_exitance", c.initial_exitance, "W/m^2");
  if (c.emissivity) h5.writeVector("/nodes/emissivity", *c.emissivity, "1");
  if (r.exchange) writeExchange(h5, *r.exchange, r.exchange_method);
  writeEigen(h5, r.pairs);
  h5.writeVector("/solution/exitance", r.solution.exitance.col(0), "W/m^2");
  h5.writeVector("/solution/irradiance", r.solution.irradiance.col(0), "W/m^2");
  if (r.thermal) {
    h5.writeMatrix("/solution/temperature", r.thermal->temperature.transpose(), "K");
    h5.attribute("/solution/temperature", "mode", std::string("steady"));
  }
  writeTimings(h5, r.timings_s);
  h5.attribute("/report", "truncation_residual", r.solution.max_residual);
  h5.attribute("/report", "refined", static_cast<long long>(r.solution.refined));
  h5.attribute("/report", "refine_iterations", static_cast<long long>(r.solution.refine_iterations));
  h5.attribute("/report", "view_factor_error", net.reciprocity().max_view_factor_change);
  h5.commit();
}

void printNetworkSummary(const NetworkCase& c, const NetworkRunResult& r, std::ostream& out) {
  const solver::Network& net = *r.network;
  out << "case " << c.name << ": " << net.size() << " nodes\n";
  out << std::left << std::setw(16) << "node" << std::right << std::setw(12) << "area m²" << std::setw(10) << "ρ"
      << std::setw(10) << "ε" << std::setw(14) << "M_o W/m²" << std::setw(14) << "M W/m²" << std::setw(14)
      << "H W/m²" << std::setw(12) << "F_space" << "\n";
  for (int i = 0; i < net.size(); ++i) {
    out << std::left << std::setw(16) << net.names()[static_cast<size_t>(i)] << std::right << std::setprecision(5)
        << std::setw(12) << net.area()[i] << std::setw(10) << c.reflectance[i] << std::setw(10);
    if (c.emissivity) out << (*c.emissivity)[i]; else out << "-";
    out << std::setw(14) << c.initial_exitance[i] << std::setw(14) << r.solution.exitance(i, 0) << std::setw(14)
        << r.solution.irradiance(i, 0) << std::setw(12) << net.spaceViewFactor()[i] << "\n";
  }
  out << "eigenpairs: rank " << r.pairs.rank() << " of " << net.size() << " (" << solver::toString(r.pairs.method)
      << "), largest dropped |λ| ≤ " << r.pairs.dropped_bound << " m²\n";
  out << "residual ‖M_o − (I − S G) M‖/‖M_o‖ with the full G: " << std::scientific << std::setprecision(3)
      << r.solution.max_residual << std::defaultfloat
      << (r.solution.refined ? " (refined, " + std::to_string(r.solution.refine_iterations) + " CG iterations)"
          : c.solver.refineEnabled() ? " (rank-" + std::to_string(r.pairs.rank()) + " solve already within the tolerance)"
                                     : " (eigenvector radiosity at rank " + std::to_string(r.pairs.rank()) + ", not refined)")
      << "\n";
  if (r.thermal)
    for (int i = 0; i < net.size(); ++i)
      out << "temperature " << net.names()[static_cast<size_t>(i)] << ": " << std::fixed << std::setprecision(3)
          << r.thermal->temperature(i, 0) << std::defaultfloat << " K\n";
  if (r.exchange)
    out << "exchange factors GR (" << r.exchange_method << "), Σ GR_space = " << r.exchange->gr_space.sum()
        << " m²\n";
  out << "timings:";
  for (const auto& [stage, seconds] : r.timings_s) out << " " << stage << " " << std::setprecision(3) << seconds << " s;";
  out << "\n";
}

std::optional<double> lookupNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const Expectation& x) {
  const solver::Network& net = *r.network;
  const int i = x.node.empty() ? -1 : net.indexOf(x.node);
  const int j = x.to.empty() ? -1 : net.indexOf(x.to);
  (void)c;
  if (x.quantity == "exitance") return r.solution.exitance(i, 0);
  if (x.quantity == "irradiance") return r.solution.irradiance(i, 0);
  if (x.quantity == "view_factor") return net.conductance(i, j) / net.area()[i];
  if (x.quantity == "space_view_factor") return net.spaceViewFactor()[i];
  if (x.quantity == "eigenvalue") {
    if (x.index >= r.pairs.rank()) return std::nullopt;
    return r.pairs.values[x.index];
  }
  if (!r.exchange) return std::nullopt;
  if (x.quantity == "radiative_exchange") return r.exchange->gr(i, j);
  if (x.quantity == "temperature" && r.thermal) return r.thermal->temperature(i, 0);
  if (x.quantity == "gr_space") return r.exchange->gr_space[i];
  return std::nullopt;
}

}  // namespace radnet::cases
