// IR band: radiative exchange factors and net power against closed forms.
#include "solver/radiative/exchange.hpp"
#include "test_support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace radnet;

namespace {

// Infinite parallel plates: two nodes of 1 m², each seeing only the other (F = 1).
solver::Network parallelPlates() {
  Eigen::MatrixXd f(2, 2);
  f << 0.0, 1.0, 1.0, 0.0;
  return solver::Network({"hot", "cold"}, Eigen::VectorXd::Ones(2), f);
}

solver::EigenPairs allPairs(const solver::Network& net) { return solver::denseEigenPairs(net.denseConductance()); }

}  // namespace

TEST_CASE("infinite parallel plates: q = σ(T1⁴ − T2⁴)/(1/ε1 + 1/ε2 − 1)") {
  const solver::Network net = parallelPlates();
  const double t1 = 400.0, t2 = 250.0;
  for (double e1 : {1.0, 0.5, 0.01}) {
    for (double e2 : {1.0, 0.5, 0.01}) {
      Eigen::VectorXd eps(2);
      eps << e1, e2;
      const double analytic_gr = 1.0 / (1.0 / e1 + 1.0 / e2 - 1.0);
      const double q = solver::kStefanBoltzmann * (std::pow(t1, 4) - std::pow(t2, 4)) * analytic_gr;
      INFO("ε1 = " << e1 << ", ε2 = " << e2);

      const solver::ExchangeFactors dense = solver::exchangeFactorsDense(net, eps);
      REQUIRE(dense.status == solver::Status::Converged);
      CHECK(dense.gr(0, 1) == Approx(analytic_gr).epsilon(1e-13));
      CHECK(dense.gr(0, 1) == dense.gr(1, 0));
      CHECK(std::abs(dense.gr_space[0]) < 1e-13);  // closed: nothing reaches space
      CHECK(dense.asymmetry < 1e-13);

      solver::LowRankBandSolver ir(net, allPairs(net), Eigen::VectorXd::Ones(2) - eps);
      const solver::ExchangeFactors low = solver::exchangeFactorsLowRank(net, ir, eps);
      CHECK(low.gr(0, 1) == Approx(analytic_gr).epsilon(1e-12));

      Eigen::MatrixXd temps(2, 1);
      temps << t1, t2;
      Eigen::MatrixXd power;
      const solver::BandSolution sol = solver::irNetPower(net, ir, eps, temps, Eigen::MatrixXd(), 0.0, power);
      REQUIRE(sol.status == solver::Status::Converged);
      CHECK(-power(0, 0) == Approx(q).epsilon(1e-12));
      CHECK(power(1, 0) == Approx(q).epsilon(1e-12));
      CHECK(std::abs(power(0, 0) + power(1, 0)) <= 1e-12 * q);  // energy conservation
    }
  }
}

TEST_CASE("open network: absorbed + lost to space = emitted, and GR sums to εA") {
  const int n = 40;
  const solver::Network net = test::randomNetwork(n, 17, 0.4, 0.3);
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd eps(n);
  Eigen::MatrixXd temps(n, 3);
  for (int i = 0; i < n; ++i) {
    eps[i] = 0.02 + 0.98 * u(rng);
    for (int p = 0; p < 3; ++p) temps(i, p) = 3.0 + 1997.0 * u(rng);  // 3 K … 2000 K
  }
  const solver::ExchangeFactors ex = solver::exchangeFactorsDense(net, eps);
  REQUIRE(ex.status == solver::Status::Converged);
  CHECK(((ex.gr.rowwise().sum() + ex.gr_space) - eps.cwiseProduct(net.area())).cwiseAbs().maxCoeff() <
        1e-13 * net.area().maxCoeff());
  CHECK((ex.gr.array() >= -1e-15).all());
  CHECK((ex.gr_space.array() >= -1e-13).all());

  solver::LowRankBandSolver ir(net, allPairs(net), Eigen::VectorXd::Ones(n) - eps);
  Eigen::MatrixXd power;
  const solver::BandSolution sol = solver::irNetPower(net, ir, eps, temps, Eigen::MatrixXd(), 0.0, power);
  REQUIRE(sol.status == solver::Status::Converged);
  const Eigen::MatrixXd eb = solver::kStefanBoltzmann * temps.array().pow(4).matrix();
  for (int p = 0; p < 3; ++p) {
    // Net power gained by all nodes = − power lost to space (space at 0 K).
    const double lost = ex.gr_space.dot(eb.col(p));
    const double emitted = eps.cwiseProduct(net.area()).dot(eb.col(p));
    CHECK(std::abs(power.col(p).sum() + lost) <= 1e-12 * emitted);
    // And the same per node through GR: Q_i = Σ_j σ GR_ij (T_j⁴ − T_i⁴) − σ GR_i,space T_i⁴.
    const Eigen::VectorXd by_gr =
        ex.gr * eb.col(p) - ex.gr.rowwise().sum().cwiseProduct(eb.col(p)) - ex.gr_space.cwiseProduct(eb.col(p));
    CHECK((by_gr - power.col(p)).cwiseAbs().maxCoeff() <= 1e-11 * emitted);
  }
}

TEST_CASE("exact GR by the symmetric in-place Cholesky equals E G (I − S G)⁻¹ E, a black node takes the LU") {
  // 333 nodes: the in-place inverse and Gram product run over two full 128-blocks and a
  // partial one. ε from 0.02 to 0.99 (ρ down to 0.01: the diagonal's cancellation 1e-14 of εA).
  const int n = 333;
  const solver::Network net = test::randomNetwork(n, 41, 0.3, 0.3);
  Eigen::VectorXd eps = test::uniformIn(n, 0.02, 0.99, 8);
  const Eigen::MatrixXd g = net.denseConductance();
  const auto reference = [&](const Eigen::VectorXd& e) {
    const Eigen::VectorXd s = (Eigen::VectorXd::Ones(n) - e).cwiseQuotient(net.area());
    const Eigen::MatrixXd m = Eigen::MatrixXd::Identity(n, n) - s.asDiagonal() * g;
    return Eigen::MatrixXd(e.asDiagonal() * g * m.fullPivLu().solve(Eigen::MatrixXd(e.asDiagonal())));
  };
  const double scale = eps.cwiseProduct(net.area()).maxCoeff();
  const solver::ExchangeFactors chol = solver::exchangeFactorsDense(net, eps);
  REQUIRE(chol.status == solver::Status::Converged);
  CHECK(chol.method == "dense Cholesky");
  // Both are backward stable on I − S G (condition ≤ 1/min ε here): 1e-12 of the largest εA.
  CHECK((chol.gr - reference(eps)).cwiseAbs().maxCoeff() <= 1e-12 * scale);
  CHECK(chol.gr == chol.gr.transpose());
  CHECK(((chol.gr.rowwise().sum() + chol.gr_space) - eps.cwiseProduct(net.area())).cwiseAbs().maxCoeff() <= 1e-13 * scale);
  eps[17] = 1.0;  // no S⁻¹ for a black node: the LU, the same answer
  const solver::ExchangeFactors lu = solver::exchangeFactorsDense(net, eps);
  CHECK(lu.method == "dense LU");
  CHECK((lu.gr - reference(eps)).cwiseAbs().maxCoeff() <= 1e-12 * scale);
}

TEST_CASE("planet IR as an external irradiance: a black plate facing it alone absorbs εAE") {
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(1, 1);
  const solver::Network net({"plate"}, Eigen::VectorXd::Constant(1, 2.0), f);
  Eigen::VectorXd eps = Eigen::VectorXd::Constant(1, 0.8);
  solver::LowRankBandSolver ir(net, allPairs(net), Eigen::VectorXd::Constant(1, 0.2));
  Eigen::MatrixXd temps = Eigen::MatrixXd::Constant(1, 1, 0.0);
  Eigen::MatrixXd e_ext = Eigen::MatrixXd::Constant(1, 1, 237.0);
  Eigen::MatrixXd power;
  solver::irNetPower(net, ir, eps, temps, e_ext, 0.0, power);
  CHECK(power(0, 0) == Approx(0.8 * 2.0 * 237.0).epsilon(1e-14));
}

namespace {

double norm2(const Eigen::MatrixXd& m) { return Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues()[0]; }

}  // namespace

TEST_CASE("truncated exchange factors: direct exchange exact, only the reflections truncated") {
  const int n = 150;
  const solver::Network net = test::randomNetwork(n, 23, 0.3, 0.2);
  const Eigen::VectorXd eps = test::uniformIn(n, 0.2, 0.9, 5);
  const Eigen::MatrixXd g = net.denseConductance();
  const solver::ExchangeFactors dense = solver::exchangeFactorsDense(net, eps);
  REQUIRE(dense.status == solver::Status::Converged);
  const solver::EigenPairs all = allPairs(net);
  const Eigen::VectorXd rho = Eigen::VectorXd::Ones(n) - eps;
  const Eigen::MatrixXd s = rho.cwiseQuotient(net.area()).asDiagonal();
  const Eigen::MatrixXd id = Eigen::MatrixXd::Identity(n, n);
  const Eigen::MatrixXd gk_full = g * (id - s * g).inverse();  // G K
  for (int k : {10, 40, n}) {
    const solver::EigenPairs pairs = solver::truncate(all, k);
    const solver::LowRankBandSolver ir(net, pairs, rho);
    const solver::ExchangeFactors low = solver::exchangeFactorsLowRank(net, ir, eps);
    REQUIRE(low.status == solver::Status::Converged);
    const double error = norm2(low.gr - dense.gr);
    // With D = G − G'_k (‖D‖₂ = |λ_k+1|) and K = (I − S G)⁻¹, K' likewise for G'_k:
    // G K − G' K' − D = D S G' K' + G K S D K', so the error is at most
    // ‖E‖² |λ_k+1| ‖S‖ (‖G' K'‖ + ‖G K‖ ‖K'‖): first order in the truncation AND in the
    // reflectance. The pure E V C Vᵀ E form also carries E D K' E, zeroth order in ρ.
    const double dropped = k < n ? std::abs(all.values[k]) : 0.0;
    const Eigen::MatrixXd gp = solver::reconstruct(pairs);
    const Eigen::MatrixXd kp = (id - s * gp).inverse();
    const double bound = std::pow(eps.maxCoeff(), 2) * dropped * norm2(s) * (norm2(gp * kp) + norm2(gk_full) * norm2(kp));
    const Eigen::MatrixXd w = eps.asDiagonal() * pairs.vectors;
    const Eigen::MatrixXd pure = w * ir.core() * w.transpose();
    const double pure_error = norm2(pure - dense.gr);
    INFO("k = " << k << ": error " << error << ", bound " << bound << ", pure low-rank error " << pure_error);
    CHECK(error <= bound + 1e-12 * norm2(dense.gr));
    if (k < n) CHECK(error < 0.25 * pure_error);  // 6.5× smaller here (ρ = 0.1–0.8, a flat spectrum)
    else CHECK(error < 1e-12 * norm2(dense.gr));
  }
  SECTION("black surfaces: GR = G exactly at any rank") {
    const solver::LowRankBandSolver black(net, solver::truncate(all, 10), Eigen::VectorXd::Zero(n));
    const solver::ExchangeFactors ex = solver::exchangeFactorsLowRank(net, black, Eigen::VectorXd::Ones(n));
    CHECK((ex.gr - g).cwiseAbs().maxCoeff() < 1e-13 * g.cwiseAbs().maxCoeff());
  }
}
