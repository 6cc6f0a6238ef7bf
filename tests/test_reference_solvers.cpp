// Every reference solver against dense LU on networks with concave nodes and ρ = 0 nodes.
#include "solver/radiative/reference_solvers.hpp"
#include "test_support.hpp"

#include <catch2/catch.hpp>

using namespace radnet;

TEST_CASE("reference solvers agree with dense LU") {
  for (unsigned seed : {3u, 4u}) {
    const int n = 60;
    const solver::Network net = test::randomNetwork(n, seed, 0.2, 0.3);
    const Eigen::MatrixXd g = net.denseConductance();
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    Eigen::VectorXd rho(n), mo(n);
    for (int i = 0; i < n; ++i) {
      rho[i] = 0.05 + 0.9 * u(rng);
      mo[i] = u(rng) < 0.3 ? 100.0 * u(rng) : 0.0;
    }
    const solver::BandSystem sys{g, net.area(), rho};
    const Eigen::VectorXd lu = solver::solveDenseLU(sys, mo).exitance;
    // Update-based stops at 1e-13 leave an error below ~1e-12/(1 − spectral radius);
    // the spectral radius of S G is below 0.95 here, so 1e-10 is a safe bound.
    solver::IterativeOptions opt;
    opt.tolerance = 1e-13;
    const auto jacobi = solver::solveJacobi(sys, mo, opt);
    const auto gs = solver::solveGaussSeidel(sys, mo, opt);
    const auto sw = solver::solveSouthwell(sys, mo, opt);
    const auto cg = solver::solveConjugateGradient(sys, mo, opt);
    for (const auto* r : {&jacobi, &gs, &sw, &cg}) {
      INFO("seed " << seed << " status " << solver::toString(r->status) << " iterations " << r->iterations << " "
                   << r->message);
      CHECK(r->status == solver::Status::Converged);
      CHECK(test::relativeError(r->exitance, lu) < 1e-10);
    }
    // Gauss–Seidel needs fewer sweeps than Jacobi on this diagonally dominant system.
    CHECK(gs.iterations < jacobi.iterations);
  }
}

TEST_CASE("CG requires ρ > 0, the others accept ρ = 0 nodes (their M_i = M_o,i)") {
  const solver::Network net = test::randomNetwork(20, 9);
  const Eigen::MatrixXd g = net.denseConductance();
  Eigen::VectorXd rho = Eigen::VectorXd::Constant(20, 0.5);
  rho[3] = 0.0;
  Eigen::VectorXd mo = Eigen::VectorXd::Zero(20);
  mo[0] = 1.0;
  mo[3] = 7.0;
  const solver::BandSystem sys{g, net.area(), rho};
  CHECK_THROWS_AS(solver::solveConjugateGradient(sys, mo), std::invalid_argument);
  const auto lu = solver::solveDenseLU(sys, mo);
  CHECK(lu.exitance[3] == Approx(7.0).epsilon(1e-14));
  const auto sw = solver::solveSouthwell(sys, mo);
  CHECK(test::relativeError(sw.exitance, lu.exitance) < 1e-8);
}
