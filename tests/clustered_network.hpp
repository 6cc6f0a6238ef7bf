#pragma once
// A synthetic sparse radiative network for the tests of factored GR and the thermal solver on it.
#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <random>
#include <string>
#include <vector>

namespace radnet::test {

// A network of n nodes in clusters of 20 that see each other (and a few links between
// clusters): F about 2 % non-zero, so the network stores it sparse, as a satellite's is.
// Row sums of F at most 0.9 (the rest to space); A F symmetric by construction.
struct ClusteredNetwork {
  Eigen::VectorXd area;
  Eigen::SparseMatrix<double> view_factors;
};

inline ClusteredNetwork clusteredNetwork(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  ClusteredNetwork c;
  c.area = Eigen::VectorXd::NullaryExpr(n, [&] { return 0.5 + 1.5 * u(rng); });
  std::vector<Eigen::Triplet<double>> g;
  const auto link = [&](int i, int j) {
    const double v = u(rng) * std::min(c.area[i], c.area[j]);
    g.emplace_back(i, j, v), g.emplace_back(j, i, v);
  };
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < std::min(n, (i / 20 + 1) * 20); ++j) link(i, j);
    if (i + 37 < n) link(i, i + 37);  // across clusters
  }
  Eigen::SparseMatrix<double> conductance(n, n);
  conductance.setFromTriplets(g.begin(), g.end());
  const Eigen::VectorXd row_share = (conductance * Eigen::VectorXd::Ones(n)).cwiseQuotient(c.area);
  conductance *= 0.9 / row_share.maxCoeff();
  c.view_factors = c.area.cwiseInverse().asDiagonal() * conductance;
  return c;
}

inline std::vector<std::string> names(int n) {
  std::vector<std::string> out;
  for (int i = 0; i < n; ++i) out.push_back("n" + std::to_string(i));
  return out;
}

}  // namespace radnet::test
