// Network validation and the reciprocity correction.
#include "solver/radiative/network.hpp"
#include "test_support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace radnet;
using Catch::Matchers::Contains;

namespace {

solver::Network twoNodes(double f01, double f10, double a0 = 1.0, double a1 = 1.0, solver::NetworkTolerances tol = {}) {
  Eigen::MatrixXd f(2, 2);
  f << 0.0, f01, f10, 0.0;
  Eigen::VectorXd a(2);
  a << a0, a1;
  return solver::Network({"a", "b"}, a, f, {}, tol);
}

}  // namespace

TEST_CASE("network: invalid data is rejected with a message naming the node") {
  CHECK_THROWS_WITH(twoNodes(-0.1, 0.5), Contains("F[0][1]") && Contains("'a'"));
  CHECK_THROWS_WITH(twoNodes(std::nan(""), 0.5), Contains("finite"));
  CHECK_THROWS_WITH(twoNodes(1.2, 0.5), Contains("sum to 1.2"));
  CHECK_THROWS_WITH(twoNodes(0.5, 0.5, 0.0), Contains("area") && Contains("'a'"));
  CHECK_THROWS_WITH(twoNodes(0.5, 0.5, 1.0, -2.0), Contains("area") && Contains("'b'"));
  CHECK_THROWS_WITH(twoNodes(0.5, 0.5, 1.0, std::numeric_limits<double>::infinity()), Contains("area"));
  // A_0 F_01 = 0.5 but A_1 F_10 = 0.2: the correction would move F by 0.15 > 0.01.
  CHECK_THROWS_WITH(twoNodes(0.5, 0.2), Contains("reciprocity") && Contains("'a'") && Contains("'b'"));
  Eigen::MatrixXd f = Eigen::MatrixXd::Zero(2, 2);
  CHECK_THROWS_WITH(solver::Network({"x", "x"}, Eigen::VectorXd::Ones(2), f), Contains("used twice"));
  CHECK_THROWS_WITH(solver::Network({"x"}, Eigen::VectorXd::Ones(1), f), Contains("2×2") && Contains("1×1"));
}

TEST_CASE("network: reciprocity correction makes G symmetric and reports the largest move") {
  // A = (1, 2); A_0 F_01 = 0.40, A_1 F_10 = 2 × 0.19 = 0.38: G_01 = 0.39.
  const solver::Network net = twoNodes(0.40, 0.19, 1.0, 2.0, solver::NetworkTolerances{1e-3, 0.02});
  const Eigen::MatrixXd g = net.denseConductance();
  CHECK(g(0, 1) == Approx(0.39).epsilon(1e-15));
  CHECK(g(1, 0) == g(0, 1));
  // Moves: F_01 by 0.01, F_10 by 0.005; reported in view-factor units: 0.02/(2·min A) = 0.01.
  CHECK(net.reciprocity().max_view_factor_change == Approx(0.01).epsilon(1e-12));
  CHECK(net.reciprocity().worst_from == 1);
  CHECK(net.reciprocity().worst_to == 0);
  // Closure: F_space = 1 − Σ_j F_ij with the corrected F.
  CHECK(net.spaceViewFactor()[0] == Approx(1.0 - 0.39).epsilon(1e-14));
  CHECK(net.spaceViewFactor()[1] == Approx(1.0 - 0.195).epsilon(1e-14));
}

TEST_CASE("network: conservation Σ_j F_ij + F_space,i = 1 and A_i F_ij = A_j F_ji on random networks") {
  for (unsigned seed : {1u, 2u, 3u}) {
    const solver::Network net = test::randomNetwork(40, seed);
    const Eigen::MatrixXd f = net.viewFactors();
    const Eigen::VectorXd closure = f.rowwise().sum() + net.spaceViewFactor();
    CHECK((closure.array() - 1.0).abs().maxCoeff() < 1e-13);
    const Eigen::MatrixXd af = net.area().asDiagonal() * f;
    CHECK((af - af.transpose()).cwiseAbs().maxCoeff() < 1e-13 * af.cwiseAbs().maxCoeff());
  }
}

TEST_CASE("network: sparse and dense storage agree") {
  const solver::Network dense = test::randomNetwork(30, 7);
  const Eigen::MatrixXd f = dense.viewFactors();
  const Eigen::SparseMatrix<double> fs = f.sparseView();
  const solver::Network sparse(test::nodeNames(30), dense.area(), fs, {}, solver::NetworkTolerances{1e-12, 1e-12});
  CHECK((sparse.denseConductance() - dense.denseConductance()).cwiseAbs().maxCoeff() < 1e-14);
  const Eigen::MatrixXd x = Eigen::MatrixXd::Random(30, 3);
  CHECK((sparse.applyConductance(x) - dense.applyConductance(x)).norm() < 1e-13);
  CHECK((sparse.spaceViewFactor() - dense.spaceViewFactor()).cwiseAbs().maxCoeff() < 1e-14);
  CHECK(sparse.spectralBound() == Approx(dense.spectralBound()));
}

TEST_CASE("network: blocked fraction enters closure, Gershgorin bound covers the spectrum (§12, eq. 38)") {
  Eigen::MatrixXd f(2, 2);
  f << 0.0, 0.5, 0.5, 0.0;
  Eigen::VectorXd blocked(2);
  blocked << 0.2, 0.6;
  CHECK_THROWS_WITH(solver::Network({"a", "b"}, Eigen::VectorXd::Ones(2), f, blocked), Contains("blocked"));
  blocked << 0.2, 0.1;
  const solver::Network net({"a", "b"}, Eigen::VectorXd::Ones(2), f, blocked);
  CHECK(net.spaceViewFactor()[0] == Approx(0.3));
  CHECK(net.spaceViewFactor()[1] == Approx(0.4));
  const solver::Network room = test::seedRoom();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(room.denseConductance());
  CHECK(es.eigenvalues().cwiseAbs().maxCoeff() <= room.spectralBound() + 1e-12);
  CHECK(room.spectralBound() <= room.area().maxCoeff() * (1 + 1e-3));  // closed room: bound ≈ area
}

TEST_CASE("network: property ranges are checked per node") {
  const solver::Network net = test::seedRoom();
  Eigen::VectorXd eps = Eigen::VectorXd::Constant(6, 0.5);
  eps[3] = 1.5;
  CHECK_THROWS_WITH(solver::checkRange(net, eps, "emissivity", 0.0, 1.0), Contains("'side1'") && Contains("1.5"));
  eps[3] = std::nan("");
  CHECK_THROWS_AS(solver::checkRange(net, eps, "emissivity", 0.0, 1.0), solver::NetworkError);
}
