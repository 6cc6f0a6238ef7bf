#pragma once
// A thermal network fixture for the solver's thermal tests: n free nodes, nothing linked.
#include "solver/thermal/temperatures.hpp"

#include <limits>
#include <tuple>
#include <vector>

namespace radnet::test {

inline solver::ThermalNetwork emptyThermalNetwork(int n) {
  solver::ThermalNetwork net;
  net.gr = Eigen::MatrixXd::Zero(n, n);
  net.gr_space = Eigen::VectorXd::Zero(n);
  net.conductors.resize(n, n);
  net.capacitance = Eigen::VectorXd::Zero(n);
  net.dissipation = Eigen::VectorXd::Zero(n);
  net.fixed_temperature = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  net.space_temperature = 3.0;
  return net;
}

/// Sets the network's constant conductors (i, j, W/K), both directions.
inline void setConductors(solver::ThermalNetwork& net, const std::vector<std::tuple<int, int, double>>& links) {
  std::vector<Eigen::Triplet<double>> t;
  for (const auto& [i, j, k] : links) {
    t.emplace_back(i, j, k);
    t.emplace_back(j, i, k);
  }
  net.conductors.setFromTriplets(t.begin(), t.end());
}

}  // namespace radnet::test
