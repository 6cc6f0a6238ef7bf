// The rank of the decomposition a posteriori (solver/radiative/rank_probe.hpp): the kept rank meets
// its targets when checked independently (dense LU, fresh right-hand sides), half of it
// does not, and it is far below what the a-priori bound keeps.
#include "solver/radiative/exchange.hpp"
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/policy.hpp"
#include "solver/radiative/rank_probe.hpp"
#include "test_support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace radnet;

namespace {

// Two parallel 1 m × 1 m plates 0.5 m apart, each split m × m, facing each other and open
// to space at the sides: the centre-to-centre form factor cos θ_i cos θ_j A_j / (π r²)
// (exactly reciprocal, never singular across the gap). Its spectrum decays like a real
// spacecraft's, unlike a closed room's.
solver::Network facingPlates(int m) {
  const double gap = 0.5, a = 1.0 / (m * m);
  const int half = m * m, n = 2 * half;
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(n, n);
  for (int p = 0; p < half; ++p)
    for (int q = 0; q < half; ++q) {
      const double dx = (p % m - q % m) / double(m), dy = (p / m - q / m) / double(m);
      const double r2 = dx * dx + dy * dy + gap * gap;
      g(p, half + q) = g(half + q, p) = gap * gap / (M_PI * r2 * r2) * a * a;
    }
  const Eigen::VectorXd area = Eigen::VectorXd::Constant(n, a);
  return solver::Network(test::nodeNames(n), area, area.cwiseInverse().asDiagonal() * g);
}

// Residual of the rank-k answer for right-hand sides mo, with the full G (independent of
// the probe's own code path: dense G, explicit formula).
double rankKResidual(const solver::Network& net, const solver::EigenPairs& all, int k, const Eigen::VectorXd& rho,
                     const Eigen::MatrixXd& mo) {
  const solver::LowRankBandSolver band(net, solver::truncate(all, k), rho);
  const Eigen::MatrixXd m = band.solve(mo).exitance;
  const Eigen::MatrixXd s = rho.cwiseQuotient(net.area()).asDiagonal();
  const Eigen::MatrixXd r = mo - (m - s * net.denseConductance() * m);
  return (r.colwise().norm().array() / mo.colwise().norm().array()).maxCoeff();
}

// Sunlit-patch right-hand sides: one side of a plate lit, 100 W/m², the rest dark.
Eigen::MatrixXd halfLit(int n, int columns, unsigned seed) {
  std::mt19937_64 rng(seed);
  Eigen::MatrixXd mo = Eigen::MatrixXd::Zero(n, columns);
  for (int c = 0; c < columns; ++c) {
    const int start = static_cast<int>(rng() % (n / 2));
    for (int i = start; i < start + n / 4; ++i) mo(i, c) = 100.0;
  }
  return mo;
}

}  // namespace

TEST_CASE("a-posteriori rank: meets its band target, half of it does not, far below the a-priori rank") {
  const solver::Network net = facingPlates(12);  // n = 288
  const int n = net.size();
  const Eigen::VectorXd rho = test::uniformIn(n, 0.1, 0.9, 3);
  const double target = 1e-3;
  solver::RankTargets targets;
  targets.reflectance = rho;
  targets.band_residual = target;
  solver::RankProbe probe(net, targets);
  const solver::EigenPairs all = solver::denseEigenPairs(net.denseConductance());
  const int k = probe(all);
  REQUIRE(k > 0);
  REQUIRE(k < n);
  const int apriori = solver::rankForTolerance(all.values, target, rho.cwiseQuotient(net.area()).maxCoeff());
  INFO("a-posteriori rank " << k << ", a-priori rank " << apriori);
  CHECK(k < apriori);  // 36 against 56 here (uniform areas: s_max is every node's s)

  CHECK(rankKResidual(net, all, k, rho, Eigen::MatrixXd::Ones(n, 1)) <= target);
  if (k / 2 >= solver::RankProbe::kMinRank) CHECK(probe.measure(all, k / 2).band_residual > target);
  // Right-hand sides the probes never saw: a lit quarter of the nodes. Within 3× the target
  // (the probes' random fields excite every eigenvector, lit patches mostly the leading ones).
  CHECK(rankKResidual(net, all, k, rho, halfLit(n, 8, 11)) <= 3 * target);
}

TEST_CASE("a-posteriori rank: GR from the pairs within the exchange target on fresh temperature fields") {
  const solver::Network net = facingPlates(12);
  const int n = net.size();
  const Eigen::VectorXd eps = test::uniformIn(n, 0.2, 0.9, 5);
  const Eigen::VectorXd rho = Eigen::VectorXd::Ones(n) - eps;
  solver::SolverSettings settings;
  settings.tolerance = 1e-4;
  settings.refine = false;  // GR (and the band answers) then come from the pairs
  const solver::EigenPairs pairs = solver::policy::decomposeForBands(net, rho, settings);
  REQUIRE(pairs.status == solver::Status::Converged);
  CHECK(pairs.rank_rule.rfind("a posteriori", 0) == 0);
  CHECK(pairs.probe_exchange_error <= settings.tolerance);
  CHECK(pairs.rank() < n / 2);
  const solver::ExchangeFactors low = solver::policy::exchangeFactors(net, pairs, eps, settings);
  const solver::ExchangeFactors exact = solver::exchangeFactorsDense(net, eps);
  REQUIRE(low.status == solver::Status::Converged);
  // σT⁴ of fields between 150 K and 350 K, normalised to their maximum as the probes are.
  for (unsigned seed : {21u, 22u}) {
    const Eigen::VectorXd t = test::uniformIn(n, 150.0, 350.0, seed);
    const Eigen::VectorXd x = t.array().pow(4) / std::pow(t.maxCoeff(), 4);
    const Eigen::VectorXd error = ((low.gr - exact.gr) * x).cwiseAbs().cwiseQuotient(eps.cwiseProduct(net.area()));
    INFO("rank " << pairs.rank() << ", largest GR x error " << error.maxCoeff() << " of ε A");
    CHECK(error.maxCoeff() <= 3 * settings.tolerance);
  }
}

TEST_CASE("a-posteriori rank: Lanczos grows the pairs until the probes are met, explicit ranks are kept") {
  const solver::Network net = facingPlates(12);
  const Eigen::VectorXd rho = test::uniformIn(net.size(), 0.1, 0.9, 3);
  solver::SolverSettings settings;
  settings.tolerance = 1e-4;
  settings.method = solver::EigenMethod::Lanczos;
  const solver::EigenPairs lanczos = solver::policy::decomposeForBands(net, rho, settings);
  REQUIRE(lanczos.status == solver::Status::Converged);
  CHECK(lanczos.rank_rule.rfind("a posteriori", 0) == 0);
  CHECK(lanczos.probe_residual <= solver::policy::kRefinedStartResidual);  // refinement on: a good start suffices
  settings.rank = 40;
  const solver::EigenPairs fixed = solver::policy::decomposeForBands(net, rho, settings);
  CHECK(fixed.rank() == 40);
  CHECK(fixed.rank_rule == "explicit");
}

TEST_CASE("a-posteriori rank: a flat spectrum stops the growth when refinement finishes the solve") {
  // A random dense network: its eigenvalues barely decay, so doubling the pairs buys little.
  const solver::Network net = test::randomNetwork(600, 41, 0.3, 0.2);
  const Eigen::VectorXd rho = test::uniformIn(600, 0.5, 0.9, 7);
  solver::RankTargets targets;
  targets.reflectance = rho;
  targets.band_residual = 1e-6;  // out of reach of any rank short of most of the spectrum
  solver::RankProbe probe(net, targets);
  solver::EigenRequest req;
  req.tolerance = 1e-12;
  req.method = solver::EigenMethod::Lanczos;
  req.max_rank = 300;
  req.accept = [&probe](const solver::EigenPairs& found) { return probe(found); };
  const solver::EigenPairs pairs = solver::decomposeConductance(net, req);
  REQUIRE(pairs.status == solver::Status::Converged);
  INFO("rank " << pairs.rank() << ": " << pairs.rank_rule << " / " << probe.rule());
  CHECK(pairs.rank() < 300);
  CHECK(probe.rule().find("flat") != std::string::npos);
}

TEST_CASE("band solve to a tolerance: CG from the rank-k answer or dense LU, whichever is predicted cheaper") {
  const solver::Network net = facingPlates(12);  // n = 288, dense
  const int n = net.size();
  const Eigen::VectorXd rho = test::uniformIn(n, 0.1, 0.9, 3);
  const solver::EigenPairs all = solver::denseEigenPairs(net.denseConductance());
  const Eigen::MatrixXd mo = halfLit(n, 6, 13);
  const Eigen::MatrixXd s = rho.cwiseQuotient(net.area()).asDiagonal();
  const Eigen::MatrixXd exact =
      (Eigen::MatrixXd::Identity(n, n) - s * net.denseConductance()).partialPivLu().solve(mo);
  const solver::LowRankBandSolver band(net, solver::truncate(all, 8), rho);
  // A loose tolerance from a good start: one or two CG iterations beat an O(n³) LU ...
  const solver::BandSolution loose = band.solve(mo, 5e-3);
  INFO("loose: CG " << loose.predicted_refine_s << " s, LU " << loose.predicted_direct_s << " s predicted");
  CHECK(loose.predicted_refine_s < loose.predicted_direct_s);
  CHECK(loose.method == "low-rank core + CG");
  CHECK(loose.max_residual <= 5e-3);
  // ... round-off from a poor start: many products with G, the LU is cheaper at this size.
  const solver::BandSolution tight = band.solve(mo, 1e-13);
  CHECK(tight.method == "dense LU");
  CHECK(tight.predicted_direct_s < tight.predicted_refine_s);
  CHECK(tight.max_residual <= 1e-13);
  CHECK((tight.exitance - exact).norm() <= 1e-12 * exact.norm());
  // Beyond kDenseBandSolveMaxNodes the LU is never predicted (memory), whatever the tolerance.
  const int big_n = solver::policy::kDenseBandSolveMaxNodes + 1;
  std::vector<Eigen::Triplet<double>> chain;  // neighbours see 10 % of each other, equal areas
  for (int i = 0; i + 1 < big_n; ++i) {
    chain.emplace_back(i, i + 1, 0.1);
    chain.emplace_back(i + 1, i, 0.1);
  }
  Eigen::SparseMatrix<double> f(big_n, big_n);
  f.setFromTriplets(chain.begin(), chain.end());
  const solver::Network big(test::nodeNames(big_n), Eigen::VectorXd::Ones(big_n), f);
  CHECK_FALSE(solver::policy::bandSolveCost(big, 32, 360, 0.5, 1e-14).direct());
  // More columns never make CG relatively cheaper than the LU's one factorisation.
  const auto few = solver::policy::bandSolveCost(net, 8, 1, 5e-2, 1e-10);
  const auto many = solver::policy::bandSolveCost(net, 8, 1000, 5e-2, 1e-10);
  CHECK(many.refine_s / many.direct_s >= few.refine_s / few.direct_s);
}

namespace {

// Lanczos pairs at `tolerance` for bands and GR (ε's), the rank rule naming `rule`, and GR
// then exact: the dense Cholesky (every ε < 1), not from the pairs. Returns the pairs.
solver::EigenPairs decomposedWithExactGR(const solver::Network& net, const Eigen::VectorXd& eps, double tolerance,
                                         const std::string& rule) {
  solver::SolverSettings settings;
  settings.tolerance = tolerance;
  settings.method = solver::EigenMethod::Lanczos;
  const Eigen::VectorXd rho = Eigen::VectorXd::Ones(eps.size()) - eps;
  const solver::EigenPairs pairs = solver::policy::decomposeForBands(net, rho, settings, {eps});
  REQUIRE(pairs.status == solver::Status::Converged);
  INFO("rank " << pairs.rank() << " (" << pairs.rank_rule << "), GR error " << pairs.probe_exchange_error);
  CHECK(pairs.rank_rule.find(rule) != std::string::npos);
  const solver::ExchangeFactors ex = solver::policy::exchangeFactors(net, pairs, eps, settings);
  CHECK(ex.method == "dense Cholesky");
  CHECK_FALSE(ex.from_pairs);
  return pairs;
}

}  // namespace

TEST_CASE("a-posteriori rank: beyond the dense-GR size a flat spectrum hands GR to dense LU, not to a short rank") {
  // n just above kDenseExchangeMaxNodes: GR would come from the pairs, but a random network's
  // flat spectrum cannot meet a tight tolerance at any affordable rank.
  const int n = solver::policy::kDenseExchangeMaxNodes + 1;
  const solver::Network net = test::randomNetwork(n, 43, 0.3, 0.2);
  const Eigen::VectorXd eps = test::uniformIn(n, 0.3, 0.9, 9);
  const solver::EigenPairs pairs = decomposedWithExactGR(net, eps, 1e-6, "GR exact (dense)");
  CHECK(pairs.rank() < solver::SolverSettings().max_rank);
}

TEST_CASE("a-posteriori rank: the cap wins over the probes, and says so") {
  const solver::Network net = facingPlates(12);
  const Eigen::VectorXd rho = test::uniformIn(net.size(), 0.1, 0.9, 3);
  solver::SolverSettings settings;
  settings.tolerance = 1e-4;
  settings.refine = false;
  settings.max_rank = 4;  // the probes want 36 or more (first test case)
  for (solver::EigenMethod method : {solver::EigenMethod::Dense, solver::EigenMethod::Lanczos}) {
    settings.method = method;
    const solver::EigenPairs pairs = solver::policy::decomposeForBands(net, rho, settings);
    REQUIRE(pairs.status == solver::Status::Converged);
    CHECK(pairs.rank() == 4);
    CHECK(pairs.rank_rule == "rank cap");
    CHECK(pairs.probe_residual > settings.tolerance);  // measured at the kept rank: the warning's input
  }
}

TEST_CASE("a-posteriori rank: on a dense G, GR alone short and more pairs dearer than the exact GR stops the growth") {
  // A smooth kernel along a chain (G_ij ∝ exp(−((i − j)/20)²)): a spectrum that decays (the
  // GR error falls faster than 1/k, so not flat) but needs about n/10 pairs for a tight GR,
  // whose Lanczos time on the dense G is above the n³ of the exact GR: the rank stops short,
  // GR is exact (dense Cholesky, every ε < 1), not from the pairs.
  const int n = solver::policy::kDenseExchangeMaxNodes + 1;
  Eigen::MatrixXd f(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) f(i, j) = std::exp(-std::pow((i - j) / 20.0, 2));
  f /= 1.05 * f.rowwise().sum().maxCoeff();  // rows sum to at most 1/1.05: the rest is space
  const solver::Network net(test::nodeNames(n), Eigen::VectorXd::Ones(n), f);
  const Eigen::VectorXd eps = test::uniformIn(n, 0.9, 0.95, 11);  // ρ ≤ 0.1: the bands are met early, GR is not
  const solver::EigenPairs pairs =
      decomposedWithExactGR(net, eps, 1e-8, "more pairs would cost more than the exact GR");
  CHECK(pairs.probe_exchange_error > 1e-8);  // the pairs alone were short
}
