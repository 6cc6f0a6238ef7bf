#include "cases/output.hpp"

#include "cases/errors.hpp"

#include <chrono>
#include <ctime>

namespace radnet::cases {
namespace {
double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

StageTimer::StageTimer() : start_(now()) {}
double StageTimer::seconds() const { return now() - start_; }

void writeMeta(Hdf5Writer& h5, const std::string& case_name, const std::string& case_yaml) {
  const std::time_t t = std::time(nullptr);
  char created[32];
  std::strftime(created, sizeof created, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
  h5.attribute("/meta", "program", std::string("radnet"));
  h5.attribute("/meta", "version", std::string(RADNET_VERSION));
  h5.attribute("/meta", "case_name", case_name);
  h5.attribute("/meta", "created_utc", std::string(created));
  h5.writeText("/meta/case_yaml", case_yaml);
}

void writeNetwork(Hdf5Writer& h5, const solver::Network& net) {
  h5.writeStrings("/nodes/name", net.names());
  h5.writeVector("/nodes/area", net.area(), "m^2");
  h5.writeMatrix("/network/view_factors", net.viewFactors(), "1");
  h5.writeVector("/network/space_view_factor", net.spaceViewFactor(), "1");
  h5.writeMatrix("/network/conductance", net.denseConductance(), "m^2");
  h5.attribute("/network", "reciprocity_max_view_factor_change", net.reciprocity().max_view_factor_change);
  h5.attribute("/network", "closure_max_row_overshoot", net.reciprocity().max_row_overshoot);
}

void writeExchange(Hdf5Writer& h5, const solver::ExchangeFactors& ex, const std::string& method) {
  h5.writeMatrix("/network/radiative_exchange", ex.gr, "m^2");
  h5.writeVector("/network/gr_space", ex.gr_space, "m^2");
  h5.attribute("/network/radiative_exchange", "method", method);
}

void writeEigen(Hdf5Writer& h5, const solver::EigenPairs& pairs) {
  h5.writeVector("/eigen/values", pairs.values, "m^2");
  h5.writeMatrix("/eigen/vectors", pairs.vectors, "1");
  h5.attribute("/eigen", "rank", static_cast<long long>(pairs.rank()));
  h5.attribute("/eigen", "tolerance", pairs.tolerance);
  h5.attribute("/eigen", "method", std::string(solver::toString(pairs.method)));
  h5.attribute("/eigen", "largest_dropped_eigenvalue_bound", pairs.dropped_bound);
}

void writeTimings(Hdf5Writer& h5, const Timings& timings) {
  for (const auto& [stage, seconds] : timings) h5.attribute("/report", "time_" + stage + "_s", seconds);
}

solver::ExchangeFactors computeExchangeFactors(const solver::Network& net, const solver::EigenPairs& pairs,
                                               const Eigen::VectorXd& emissivity, bool full_accuracy,
                                               std::string& method) {
  constexpr int kDenseExchangeLimit = 3000;  // dense GR costs O(n³)
  solver::ExchangeFactors ex;
  if (full_accuracy && net.size() <= kDenseExchangeLimit) {
    ex = solver::exchangeFactorsDense(net, emissivity);
    method = "dense LU";
  } else {
    const solver::LowRankBandSolver ir(net, pairs, Eigen::VectorXd::Ones(net.size()) - emissivity);
    ex = solver::exchangeFactorsLowRank(net, ir, emissivity);
    method = "low rank (k = " + std::to_string(pairs.rank()) + ")";
  }
  if (ex.status != solver::Status::Converged)
    throw NumericalError(std::string("exchange factors ") + solver::toString(ex.status) + ": " + ex.message);
  return ex;
}

solver::EigenPairs decomposeForBands(const solver::Network& net, const Eigen::VectorXd& max_reflectance, int rank,
                                     double tolerance, int max_rank, solver::EigenMethod method) {
  solver::EigenRequest req;
  req.rank = rank;
  req.tolerance = tolerance;
  req.max_s = std::max(max_reflectance.cwiseQuotient(net.area()).maxCoeff(), 1e-300);
  req.max_rank = max_rank;
  req.method = method;
  return solver::decomposeConductance(net, req);
}

}  // namespace radnet::cases
