// IR band: radiative exchange factors and net power against closed forms.
#include "solver/exchange.hpp"
#include "test_support.hpp"

#include <catch2/catch.hpp>

#include <cmath>

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
