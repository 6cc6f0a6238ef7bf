// The update of a decomposition for a conductance matrix changed in some rows and columns
// (solver/radiative/pair_update.hpp, articulated parts): against a dense eigendecomposition
// of the changed matrix, the independent truth.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/network.hpp"
#include "solver/radiative/pair_update.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace radnet;

namespace {

// A symmetric conductance of n nodes (unit areas, row sums of F below 1) from a smooth kernel
// plus noise: its spectrum decays like a spacecraft's.
Eigen::MatrixXd conductance(int n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = u(rng);
  Eigen::MatrixXd g(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) g(i, j) = i == j ? 0.0 : std::exp(-4.0 * std::abs(x[i] - x[j])) / n;
  return 0.5 * (g + g.transpose());
}

solver::Network network(const Eigen::MatrixXd& g) {
  const int n = static_cast<int>(g.rows());
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) names.push_back("n" + std::to_string(i));
  return solver::Network(names, Eigen::VectorXd::Ones(n), g);  // A = 1: F = G
}

}  // namespace

TEST_CASE("pair update: a change in a few rows and columns, every pair kept, reproduces G' to rounding") {
  const int n = 120;
  const Eigen::MatrixXd g = conductance(n, 7);
  Eigen::MatrixXd moved = g;
  // Rows and columns 10..24 change (a part that turned): a symmetric perturbation of them.
  const std::vector<int> changed = {10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 0.3 / n);
  for (int i : changed)
    for (int j = 0; j < n; ++j)
      if (i != j) moved(i, j) = moved(j, i) = u(rng);
  const solver::Network base = network(g), turned = network(moved);
  const solver::EigenPairs pairs = solver::denseEigenPairs(base.denseConductance());
  const Eigen::SparseMatrix<double> change = solver::conductanceChange(base, turned, changed);
  // Outside the changed rows and columns ΔG is zero; inside it is G' − G.
  CHECK((Eigen::MatrixXd(change) - (turned.denseConductance() - base.denseConductance())).cwiseAbs().maxCoeff() < 1e-15);
  solver::PairUpdateStats stats;
  const solver::EigenPairs updated = solver::updatedPairs(pairs, change, 1e-14, 1, &stats);
  // Every pair of G kept and every component of ΔG above 1e-14: V' Λ' V'ᵀ = G' to rounding,
  // V' orthonormal, and the eigenvalues those of a dense solve of G'.
  const Eigen::MatrixXd rebuilt = solver::reconstruct(updated);
  CHECK((rebuilt - turned.denseConductance()).cwiseAbs().maxCoeff() < 1e-12);
  const Eigen::MatrixXd vtv = updated.vectors.transpose() * updated.vectors;
  CHECK((vtv - Eigen::MatrixXd::Identity(vtv.rows(), vtv.cols())).cwiseAbs().maxCoeff() < 1e-10);
  const solver::EigenPairs dense = solver::denseEigenPairs(turned.denseConductance());
  for (int j = 0; j < 10; ++j) CHECK(updated.values[j] == Approx(dense.values[j]).epsilon(1e-10));
  CHECK(stats.changed_nodes == n);  // the changed columns reach every row
  CHECK(stats.update_rank <= 2 * static_cast<int>(changed.size()));
}

TEST_CASE("pair update: truncated base pairs, a small change: the leading eigenpairs follow G'") {
  const int n = 200;
  const Eigen::MatrixXd g = conductance(n, 11);
  Eigen::MatrixXd moved = g;
  for (int i = 50; i < 56; ++i)  // six rows couple to the rest 20 % more
    for (int j = 0; j < n; ++j)
      if (i != j) moved(i, j) = moved(j, i) = 1.2 * g(i, j);
  const solver::Network base = network(g), turned = network(moved);
  const solver::EigenPairs pairs = solver::truncate(solver::denseEigenPairs(base.denseConductance()), 30);
  const solver::EigenPairs updated = solver::updatedPairs(
      pairs, solver::conductanceChange(base, turned, {50, 51, 52, 53, 54, 55}), pairs.dropped_bound);
  const solver::EigenPairs dense = solver::denseEigenPairs(turned.denseConductance());
  // Rayleigh–Ritz values interlace from below in magnitude: the leading ones within the base's
  // truncation plus the update's cut (dropped_bound) of the true ones.
  for (int j = 0; j < 5; ++j) CHECK(std::abs(updated.values[j] - dense.values[j]) <= updated.dropped_bound);
  // The truncated G'_k is closer to G' than the base's G_k is (the change is in it).
  const double before = (solver::reconstruct(pairs) - turned.denseConductance()).norm();
  const double after = (solver::reconstruct(updated) - turned.denseConductance()).norm();
  CHECK(after < before);
}
