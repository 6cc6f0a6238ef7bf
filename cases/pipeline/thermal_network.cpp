// The solver's thermal network from a case's thermal settings and its exchange factors.
#include "cases/pipeline/thermal_run.hpp"

namespace radnet::cases {
namespace {

// GR kept as D + W K Wᵀ over the whole thermal network: D padded with the lumped nodes and
// the couplings given added to it, W padded with zero rows.
std::shared_ptr<const solver::FactoredExchange> factoredExchange(const ThermalSettings& ts,
                                                                 const solver::ExchangeFactors& exchange) {
  const Eigen::Index n = ts.nodeCount(), nr = exchange.size();
  auto f = std::make_shared<solver::FactoredExchange>();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(exchange.direct.nonZeros()) + ts.radiative_couplings.size());
  for (Eigen::Index i = 0; i < exchange.direct.outerSize(); ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(exchange.direct, i); it; ++it)
      entries.emplace_back(static_cast<int>(i), static_cast<int>(it.col()), it.value());
  entries.insert(entries.end(), ts.radiative_couplings.begin(), ts.radiative_couplings.end());
  f->direct.resize(n, n);
  f->direct.setFromTriplets(entries.begin(), entries.end());  // duplicates summed, as the dense form adds them
  f->basis = Eigen::MatrixXd::Zero(n, exchange.basis.cols());
  f->basis.topRows(nr) = exchange.basis;
  f->core = exchange.core;
  return f;
}

}  // namespace

solver::ExchangeUpdate thermalExchange(const ThermalSettings& ts, const solver::ExchangeFactors& exchange) {
  const Eigen::Index n = ts.nodeCount(), nr = exchange.size();
  solver::ExchangeUpdate u;
  // The dense form (optics that follow temperature, turning parts): formed from the factors.
  u.gr = Eigen::MatrixXd::Zero(n, n);
  exchange.denseInto(u.gr.topLeftCorner(nr, nr));
  for (const auto& c : ts.radiative_couplings) u.gr(c.row(), c.col()) += c.value();
  u.gr_space = Eigen::VectorXd::Zero(n);
  u.gr_space.head(nr) = exchange.gr_space;
  return u;
}


solver::ThermalNetwork thermalNetwork(const ThermalSettings& ts, const solver::ExchangeFactors& exchange,
                                      bool keep_factored) {
  solver::ThermalNetwork net;
  if (keep_factored && exchange.factored()) {
    net.gr_factored = factoredExchange(ts, exchange);
    net.gr_space = Eigen::VectorXd::Zero(ts.nodeCount());
    net.gr_space.head(exchange.size()) = exchange.gr_space;
  } else {
    solver::ExchangeUpdate u = thermalExchange(ts, exchange);
    net.gr = std::move(u.gr);
    net.gr_space = std::move(u.gr_space);
  }
  net.conductors.resize(ts.nodeCount(), ts.nodeCount());
  net.conductors.setFromTriplets(ts.conductors.begin(), ts.conductors.end());
  net.tabled_conductors = ts.tabled_conductors;
  net.capacitance = ts.capacitance;
  net.capacitance_tables = ts.capacitance_tables;
  net.dissipation = ts.dissipation;
  net.schedules = ts.schedules;
  net.heaters = ts.heaters;
  net.fixed_temperature = ts.fixed_temperature;
  net.boundary_schedules = ts.boundary_schedules;
  net.space_temperature = ts.space_temperature;
  return net;
}

}  // namespace radnet::cases
