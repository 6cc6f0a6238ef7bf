#pragma once
// Shared fixtures: the paper's room and seeded random networks.
#include "solver/radiative/network.hpp"

#include <Eigen/Dense>

#include <random>
#include <string>
#include <vector>

namespace radnet::test {

inline std::vector<std::string> nodeNames(int n) {
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) names.push_back("n" + std::to_string(i));
  return names;
}

/// Ashdown 2001 §6: the 5 × 3 × 2.5 m room, form factors to 4 decimals.
inline solver::Network seedRoom() {
  Eigen::MatrixXd f(6, 6);
  f << 0.0000, 0.1249, 0.1249, 0.2145, 0.2145, 0.3213,  //
      0.2498, 0.0000, 0.0800, 0.2102, 0.2102, 0.2498,   //
      0.2498, 0.0800, 0.0000, 0.2102, 0.2102, 0.2498,   //
      0.2573, 0.1261, 0.1261, 0.0000, 0.2331, 0.2573,   //
      0.2573, 0.1261, 0.1261, 0.2331, 0.0000, 0.2573,   //
      0.3213, 0.1249, 0.1249, 0.2145, 0.2145, 0.0000;
  Eigen::VectorXd area(6);
  area << 15.0, 7.5, 7.5, 12.5, 12.5, 15.0;
  return solver::Network({"ceiling", "end1", "end2", "side1", "side2", "floor"}, area, f);
}

inline Eigen::VectorXd seedRoomReflectance() {
  Eigen::VectorXd rho(6);
  rho << 0.8, 0.7, 0.7, 0.7, 0.7, 0.2;
  return rho;
}

inline Eigen::VectorXd unitCeiling() { return Eigen::VectorXd::Unit(6, 0); }

/// A random network with F_space,i drawn from [0, max_space] (0: closed), some concave
/// nodes (F_ii > 0) and areas from the conductance row sums: G random, symmetric, ≥ 0,
/// A_i = Σ_j G_ij / (1 − F_space,i).
inline solver::Network randomNetwork(int n, unsigned seed, double max_space = 0.3, double concave_share = 0.2) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) {
      double v = u(rng);
      v = v * v * v;  // many weak couplings, a few strong ones, as in real scenes
      if (i == j) v = u(rng) < concave_share ? v : 0.0;
      g(i, j) = g(j, i) = v;
    }
  Eigen::VectorXd area(n);
  for (int i = 0; i < n; ++i) area[i] = g.row(i).sum() / (1.0 - max_space * u(rng));
  const Eigen::MatrixXd f = area.cwiseInverse().asDiagonal() * g;
  return solver::Network(nodeNames(n), area, f, {}, solver::NetworkTolerances{1e-12, 1e-12});
}

/// n values uniform in [lo, hi), fixed seed.
inline Eigen::VectorXd uniformIn(int n, double lo, double hi, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(rng);
  return v;
}

inline double relativeError(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

}  // namespace radnet::test
