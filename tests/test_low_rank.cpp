// The production path: the k×k core C = Λ (I − Vᵀ S V Λ)⁻¹ against direct solves.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/reference_solvers.hpp"
#include "test_support.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace radnet;

namespace {

Eigen::VectorXd randomReflectance(int n, unsigned seed, double lo = 0.05, double hi = 0.95) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(lo, hi);
  Eigen::VectorXd rho(n);
  for (int i = 0; i < n; ++i) rho[i] = u(rng);
  return rho;
}

Eigen::MatrixXd randomSources(int n, int p, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1000.0);
  Eigen::MatrixXd m(n, p);
  for (int j = 0; j < p; ++j)
    for (int i = 0; i < n; ++i) m(i, j) = u(rng);
  return m;
}

}  // namespace

TEST_CASE("low-rank core with k = n equals dense LU to 1e-10") {
  for (int n : {10, 100}) {
    const solver::Network net = test::randomNetwork(n, 11u + static_cast<unsigned>(n));
    const Eigen::VectorXd rho = randomReflectance(n, 5);
    solver::EigenRequest req;
    req.rank = n;
    const solver::EigenPairs pairs = solver::decomposeConductance(net, req);
    REQUIRE(pairs.rank() == n);
    solver::LowRankBandSolver band(net, pairs, rho);
    const Eigen::MatrixXd mo = randomSources(n, 5, 3);
    const solver::BandSolution sol = band.solve(mo);
    const Eigen::MatrixXd g = net.denseConductance();
    for (int c = 0; c < mo.cols(); ++c) {
      const Eigen::VectorXd lu = solver::solveDenseLU({g, net.area(), rho}, mo.col(c)).exitance;
      INFO("n = " << n << " column " << c);
      CHECK(test::relativeError(sol.exitance.col(c), lu) < 1e-10);
    }
    CHECK(sol.max_residual < 1e-10);
  }
}

TEST_CASE("low-rank core with k < n equals the direct solve with G'_k to 1e-10") {
  const int n = 100;
  const solver::Network net = test::randomNetwork(n, 21);
  const Eigen::VectorXd rho = randomReflectance(n, 6);
  const solver::EigenPairs all = solver::denseEigenPairs(net.denseConductance());
  for (int k : {1, 5, 20, 60}) {
    const solver::EigenPairs pairs = solver::truncate(all, k);
    solver::LowRankBandSolver band(net, pairs, rho);
    REQUIRE(band.status() == solver::Status::Converged);
    const Eigen::MatrixXd gk = solver::reconstruct(pairs);
    const Eigen::MatrixXd mo = randomSources(n, 3, 4);
    const solver::BandSolution sol = band.solve(mo);
    for (int c = 0; c < mo.cols(); ++c) {
      const Eigen::VectorXd direct = solver::solveDenseLU({gk, net.area(), rho}, mo.col(c)).exitance;
      INFO("k = " << k << " column " << c);
      CHECK(test::relativeError(sol.exitance.col(c), direct) < 1e-10);
    }
    // The interreflected flux A H' = G'_k M' is consistent with the answer: M = M_o + ρ ∘ H.
    const Eigen::MatrixXd ah = net.area().asDiagonal() * sol.irradiance;
    CHECK((ah - gk * sol.exitance).norm() < 1e-10 * ah.norm());
  }
}

TEST_CASE("a batch of right-hand sides equals column-by-column solves") {
  const int n = 50;
  const solver::Network net = test::randomNetwork(n, 31);
  const solver::EigenPairs pairs = solver::truncate(solver::denseEigenPairs(net.denseConductance()), 10);
  solver::LowRankBandSolver band(net, pairs, randomReflectance(n, 8));
  const Eigen::MatrixXd mo = randomSources(n, 7, 9);
  const solver::BandSolution batch = band.solve(mo);
  for (int c = 0; c < 7; ++c) {
    const solver::BandSolution one = band.solve(mo.col(c));
    CHECK((one.exitance.col(0) - batch.exitance.col(c)).norm() < 1e-13 * batch.exitance.col(c).norm());
  }
}

TEST_CASE("refinement reaches the full-G solution from any rank") {
  const int n = 120;
  const solver::Network net = test::randomNetwork(n, 41, 0.1);
  const Eigen::VectorXd rho = randomReflectance(n, 10, 0.0, 0.98);
  const Eigen::MatrixXd g = net.denseConductance();
  const solver::EigenPairs all = solver::denseEigenPairs(g);
  const Eigen::MatrixXd mo = randomSources(n, 4, 12);
  for (int k : {1, 8, 40}) {
    solver::LowRankBandSolver band(net, solver::truncate(all, k), rho);
    const solver::BandSolution sol = band.solve(mo, 1e-12, 500, solver::Refinement::ConjugateGradient);
    INFO("k = " << k << ": " << sol.message << ", iterations " << sol.refine_iterations);
    REQUIRE(sol.status == solver::Status::Converged);
    CHECK(sol.max_residual <= 1e-12);
    for (int c = 0; c < mo.cols(); ++c) {
      const Eigen::VectorXd lu = solver::solveDenseLU({g, net.area(), rho}, mo.col(c)).exitance;
      CHECK(test::relativeError(sol.exitance.col(c), lu) < 1e-10);
    }
  }
}

TEST_CASE("Lanczos (Spectra) eigenpairs: residual ‖G V − V Λ‖ and agreement with the dense solver") {
  for (int n : {100, 600}) {
    const solver::Network net = test::randomNetwork(n, 51u + static_cast<unsigned>(n));
    const Eigen::MatrixXd g = net.denseConductance();
    solver::EigenRequest req;
    req.rank = 12;
    req.method = solver::EigenMethod::Lanczos;
    const solver::EigenPairs lz = solver::decomposeConductance(net, req);
    REQUIRE(lz.status == solver::Status::Converged);
    REQUIRE(lz.method == solver::EigenMethod::Lanczos);
    const Eigen::MatrixXd resid = g * lz.vectors - lz.vectors * lz.values.asDiagonal();
    INFO("n = " << n << " residual " << resid.norm());
    CHECK(resid.norm() < 1e-8 * std::abs(lz.values[0]));
    const solver::EigenPairs dense = solver::denseEigenPairs(g);
    CHECK((lz.values - dense.values.head(12)).cwiseAbs().maxCoeff() < 1e-9 * std::abs(dense.values[0]));
    // Sparse storage and a function operator give the same spectrum.
    const Eigen::SparseMatrix<double> gs = g.sparseView();
    solver::SymmetricOperator op{n, [&](const double* x, double* y) {
                                   Eigen::Map<Eigen::VectorXd>(y, n) = gs * Eigen::Map<const Eigen::VectorXd>(x, n);
                                 }};
    const solver::EigenPairs fn = solver::lanczosEigenPairs(op, 12, 1000, 1e-12);
    REQUIRE(fn.status == solver::Status::Converged);
    CHECK((fn.values - lz.values).cwiseAbs().maxCoeff() < 1e-9 * std::abs(dense.values[0]));
  }
}

TEST_CASE("rank from a tolerance: the a-priori bound ‖S (G − G'_k)‖₂ ≤ tolerance holds") {
  const int n = 200;
  const solver::Network net = test::randomNetwork(n, 61);
  const Eigen::VectorXd rho = randomReflectance(n, 13);
  const Eigen::VectorXd s = rho.cwiseQuotient(net.area());
  for (auto method : {solver::EigenMethod::Dense, solver::EigenMethod::Lanczos}) {
    for (double tol : {1e-1, 1e-2, 1e-3}) {
      solver::EigenRequest req;
      req.tolerance = tol;
      req.max_s = s.maxCoeff();
      req.method = method;
      const solver::EigenPairs pairs = solver::decomposeConductance(net, req);
      REQUIRE(pairs.status == solver::Status::Converged);
      const Eigen::MatrixXd diff = s.asDiagonal() * (net.denseConductance() - solver::reconstruct(pairs));
      const double norm2 = Eigen::JacobiSVD<Eigen::MatrixXd>(diff).singularValues()[0];
      INFO(solver::toString(method) << " tolerance " << tol << ": rank " << pairs.rank() << ", ‖S(G−G')‖ " << norm2);
      CHECK(norm2 <= tol * (1 + 1e-9));
      CHECK(pairs.rank() < n);  // something was truncated: the rule is not "keep all"
      // Minimal: the last kept pair alone already breaks the rule, so one pair fewer would not do.
      if (pairs.rank() > 1) CHECK(std::abs(pairs.values[pairs.rank() - 1]) * s.maxCoeff() > tol);
    }
  }
}

TEST_CASE("a network with no exchange at all (G = 0) keeps rank 0 and solves exactly: M = M_o, H = 0") {
  // 500 nodes of one flat plate: every view factor is 0. The iterative eigensolvers fail on a
  // zero matrix ("TridiagEigen failed" before); none is needed.
  const int n = 500;
  std::vector<std::string> names;
  for (int i = 0; i < n; ++i) names.push_back("cell" + std::to_string(i));
  const solver::Network net(names, Eigen::VectorXd::Constant(n, 0.002), Eigen::MatrixXd::Zero(n, n));
  for (int rank : {0, 20}) {
    INFO("requested rank " << rank);
    solver::EigenRequest req;
    req.rank = rank;
    const solver::EigenPairs pairs = solver::decomposeConductance(net, req);
    REQUIRE(pairs.status == solver::Status::Converged);
    CHECK(pairs.rank() == 0);
    const solver::LowRankBandSolver band(net, pairs, Eigen::VectorXd::Constant(n, 0.3));
    const Eigen::MatrixXd mo = Eigen::MatrixXd::Random(n, 3).cwiseAbs();
    const solver::BandSolution s = band.solve(mo, 1e-12, 50, solver::Refinement::ConjugateGradient);
    REQUIRE(s.status == solver::Status::Converged);
    CHECK((s.exitance - mo).cwiseAbs().maxCoeff() == 0.0);
    CHECK(s.irradiance.cwiseAbs().maxCoeff() == 0.0);
  }
}

TEST_CASE("Lanczos growing its rank past G's non-zero eigenvalues keeps orthonormal pairs that rebuild G") {
  // 800 nodes of which only 24 see each other (a closed cluster): G has at most 24 non-zero
  // eigenvalues. A rank grown 16 → 32 → 64 asks the later runs, which work on G with the
  // pairs found deflated, for pairs of a zero eigenvalue, whose eigenvectors may mix with the
  // deflated ones. Truth: VᵀV = I and V Λ Vᵀ = G, to round-off.
  const int n = 800, m = 24;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> share(0.2, 1.0);
  std::vector<Eigen::Triplet<double>> f;
  for (int i = 0; i < m; ++i) {
    std::vector<double> row(m, 0.0);
    double total = 0.0;
    for (int j = 0; j < m; ++j) total += (row[j] = i == j ? 0.0 : share(rng));
    for (int j = 0; j < m; ++j)
      if (row[j] > 0) f.emplace_back(i, j, 0.9 * row[j] / total);
  }
  Eigen::SparseMatrix<double> view_factors(n, n);
  view_factors.setFromTriplets(f.begin(), f.end());
  const solver::Network net(test::nodeNames(n), Eigen::VectorXd::Constant(n, 0.01), view_factors, {},
                            solver::NetworkTolerances{1e-3, 1.0});
  REQUIRE(net.isSparse());
  solver::EigenRequest req;
  req.tolerance = 1e-300;  // never met by a non-zero pair: the rank grows to the cap
  req.max_rank = 64;
  req.method = solver::EigenMethod::Lanczos;
  const solver::EigenPairs pairs = solver::decomposeConductance(net, req);
  REQUIRE(pairs.status == solver::Status::Converged);
  INFO("rank " << pairs.rank() << ", rule " << pairs.rank_rule);
  const Eigen::MatrixXd vtv = pairs.vectors.transpose() * pairs.vectors;
  CHECK((vtv - Eigen::MatrixXd::Identity(pairs.rank(), pairs.rank())).cwiseAbs().maxCoeff() < 1e-10);
  const Eigen::MatrixXd g = net.denseConductance();
  CHECK((solver::reconstruct(pairs) - g).cwiseAbs().maxCoeff() < 1e-10 * g.cwiseAbs().maxCoeff());
}
