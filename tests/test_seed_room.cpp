// The paper's own numbers (Ashdown 2001, §6–9) as the independent truth.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/reference_solvers.hpp"
#include "test_support.hpp"

#include <catch2/catch.hpp>

using namespace radnet;
using Catch::Matchers::WithinAbs;

namespace {

// The paper prints 4 decimals: agreement "to 4 decimals" means within half a unit of the
// last printed digit (5e-5), plus the effect of its 4-decimal form factors (checked below
// to stay inside that bound).
constexpr double kFourDecimals = 5e-5;

const double kPaperM[6] = {1.2343, 0.3684, 0.3684, 0.3713, 0.3713, 0.1296};
const double kPaperM2[6] = {1.2431, 0.3695, 0.3695, 0.3484, 0.3484, 0.1322};

}  // namespace

TEST_CASE("seed room: full solution M matches the paper to 4 decimals (eq. 18)") {
  const solver::Network net = test::seedRoom();
  const Eigen::MatrixXd g = net.denseConductance();
  const Eigen::VectorXd rho = test::seedRoomReflectance();
  const auto res = solver::solveDenseLU({g, net.area(), rho}, test::unitCeiling());
  REQUIRE(res.status == solver::Status::Converged);
  for (int i = 0; i < 6; ++i) {
    INFO("node " << i << " M = " << res.exitance[i]);
    CHECK_THAT(res.exitance[i], WithinAbs(kPaperM[i], kFourDecimals));
  }
}

TEST_CASE("seed room: eigenvalues within 0.005 of the paper's") {
  const solver::Network net = test::seedRoom();
  const solver::EigenPairs pairs = solver::denseEigenPairs(net.denseConductance());
  const double paper[6] = {12.401, -4.819, -2.913, -2.639, -1.429, -0.600};
  REQUIRE(pairs.rank() == 6);
  for (int i = 0; i < 6; ++i) {
    INFO("λ_" << i + 1 << " = " << pairs.values[i]);
    CHECK_THAT(pairs.values[i], WithinAbs(paper[i], 0.005));
  }
}

TEST_CASE("seed room: rank-2 solution M'_2 matches the paper to 4 decimals (low-rank core)") {
  const solver::Network net = test::seedRoom();
  solver::EigenRequest req;
  req.rank = 2;
  const solver::EigenPairs pairs = solver::decomposeConductance(net, req);
  REQUIRE(pairs.rank() == 2);
  solver::LowRankBandSolver band(net, pairs, test::seedRoomReflectance());
  REQUIRE(band.status() == solver::Status::Converged);
  const solver::BandSolution sol = band.solve(test::unitCeiling());
  for (int i = 0; i < 6; ++i) {
    INFO("node " << i << " M'_2 = " << sol.exitance(i, 0));
    CHECK_THAT(sol.exitance(i, 0), WithinAbs(kPaperM2[i], kFourDecimals));
  }
  // The paper: relative 2-norm error of M'_2 against M is 2.7 %; our residual report
  // must flag a truncation error of that order, not hide it.
  CHECK(sol.max_residual > 1e-2);
  CHECK_FALSE(sol.refined);
}

TEST_CASE("seed room: refinement turns M'_2 into the full-G answer") {
  const solver::Network net = test::seedRoom();
  solver::EigenRequest req;
  req.rank = 2;
  const solver::EigenPairs pairs = solver::decomposeConductance(net, req);
  solver::LowRankBandSolver band(net, pairs, test::seedRoomReflectance());
  const solver::BandSolution sol = band.solve(test::unitCeiling(), 1e-13, 500, solver::Refinement::ConjugateGradient);
  REQUIRE(sol.status == solver::Status::Converged);
  CHECK(sol.refined);
  CHECK(sol.max_residual <= 1e-13);
  for (int i = 0; i < 6; ++i) CHECK_THAT(sol.exitance(i, 0), WithinAbs(kPaperM[i], kFourDecimals));
}

TEST_CASE("seed room: Jacobi reaches 0.1 % within 13 iterations (§9)") {
  const solver::Network net = test::seedRoom();
  const Eigen::MatrixXd g = net.denseConductance();
  const Eigen::VectorXd rho = test::seedRoomReflectance();
  const Eigen::VectorXd exact = solver::solveDenseLU({g, net.area(), rho}, test::unitCeiling()).exitance;
  int first_within = -1;
  solver::IterativeOptions opt;
  opt.tolerance = 1e-14;
  opt.max_iterations = 60;
  opt.observer = [&](int r, const Eigen::VectorXd& m) {
    if (first_within < 0 && test::relativeError(m, exact) < 1e-3) first_within = r;
  };
  const auto res = solver::solveJacobi({g, net.area(), rho}, test::unitCeiling(), opt);
  INFO("first iteration within 0.1 %: " << first_within);
  CHECK(first_within > 0);
  CHECK(first_within <= 13);
  CHECK(test::relativeError(res.exitance, exact) < 1e-12);
}

TEST_CASE("seed room: the paper's eigenvector iteration with k = 2 reaches 0.1 % of M'_2 within 14 iterations") {
  const solver::Network net = test::seedRoom();
  const Eigen::VectorXd rho = test::seedRoomReflectance();
  const solver::EigenPairs pairs = solver::truncate(solver::denseEigenPairs(net.denseConductance()), 2);
  // Reference: direct solve with G'_2 (eq. 18 with G'_2).
  const Eigen::MatrixXd g2 = solver::reconstruct(pairs);
  const Eigen::VectorXd m2 = solver::solveDenseLU({g2, net.area(), rho}, test::unitCeiling()).exitance;
  int first_within = -1;
  solver::IterativeOptions opt;
  opt.tolerance = 1e-14;
  opt.max_iterations = 80;
  opt.observer = [&](int r, const Eigen::VectorXd& m) {
    if (first_within < 0 && test::relativeError(m, m2) < 1e-3) first_within = r;
  };
  const auto res = solver::solveEigenIteration(pairs, net.area(), rho, test::unitCeiling(), opt);
  INFO("first iteration within 0.1 %: " << first_within);
  CHECK(first_within > 0);
  CHECK(first_within <= 14);
  CHECK(res.status == solver::Status::Converged);
  CHECK(test::relativeError(res.exitance, m2) < 1e-12);
  for (int i = 0; i < 6; ++i) CHECK_THAT(res.exitance[i], WithinAbs(kPaperM2[i], kFourDecimals));
}

TEST_CASE("paper's random network (§6): G'_4 has the paper's entries, including its negative conductances") {
  Eigen::MatrixXd g(6, 6);
  g << 0.000, 0.451, 0.043, 0.027, 0.312, 0.012,  //
      0.451, 0.000, 0.384, 0.683, 0.092, 0.035,   //
      0.043, 0.384, 0.000, 0.612, 0.608, 0.015,   //
      0.027, 0.683, 0.612, 0.000, 0.016, 0.190,   //
      0.312, 0.092, 0.608, 0.016, 0.000, 0.586,   //
      0.012, 0.035, 0.015, 0.190, 0.586, 0.000;
  Eigen::MatrixXd paper(6, 6);
  paper << -0.084, 0.424, 0.083, 0.057, 0.310, 0.017,  //
      0.424, 0.004, 0.367, 0.706, 0.077, 0.069,        //
      0.083, 0.367, 0.044, 0.568, 0.641, -0.057,       //
      0.057, 0.706, 0.568, 0.003, 0.002, 0.221,        //
      0.310, 0.077, 0.641, 0.002, 0.016, 0.551,        //
      0.017, 0.069, -0.057, 0.221, 0.551, 0.078;
  const Eigen::MatrixXd g4 = solver::reconstruct(solver::truncate(solver::denseEigenPairs(g), 4));
  INFO("G'_4 =\n" << g4);
  // The paper rounds G to 3 decimals (±0.0005 per entry) and prints G'_4 to 3 decimals:
  // allow the rounding of both, 0.0015.
  CHECK((g4 - paper).cwiseAbs().maxCoeff() < 1.5e-3);
  // (The paper's areas, "the column sums of G", exceed the sums of its printed 3-decimal
  // G by up to 0.003, more than rounding explains; F = A⁻¹ G uses the printed areas.)
  CHECK_THAT(g(0, 1) / 0.848, WithinAbs(0.532, 5e-4));
}
