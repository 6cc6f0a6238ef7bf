// Temperatures on a factored GR (D + W K Wᵀ, applied as products, Newton steps by
// preconditioned GMRES: solver/thermal/jacobian.hpp) against the same GR formed n × n and
// solved by dense LU. The two networks hold the same GR to round-off, so the temperatures
// differ only by what each Newton leaves, at a tolerance far below the comparison's.
#include "clustered_network.hpp"
#include "thermal_support.hpp"

#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/exchange.hpp"
#include "solver/thermal/temperatures.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace radnet;

namespace {

struct TwoForms {
  solver::ThermalNetwork dense, factored;
  int radiative = 0;
};

// A 1,500-node clustered radiative network (F 1.6 % non-zero) with GR from 200 pairs, and
// the thermal model a shell mesh would give it: conductors along each cluster, capacitances
// ∝ area; then two lumped nodes: a box (5 W, a thermostat heater, a radiative coupling, joints
// to ten nodes) and a 280 K boundary node; a conductor tabulated against temperature.
TwoForms twoForms() {
  const int n = 1500, k = 200, total = n + 2, box = n, wall = n + 1;
  const test::ClusteredNetwork c = test::clusteredNetwork(n, 11);
  const solver::Network sparse(test::names(n), c.area, c.view_factors);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.1, 0.9);
  const Eigen::VectorXd eps = Eigen::VectorXd::NullaryExpr(n, [&] { return u(rng); });
  const solver::EigenPairs pairs = solver::truncate(solver::denseEigenPairs(sparse.denseConductance()), k);
  const solver::ExchangeFactors ex =
      solver::exchangeFactorsLowRank(sparse, solver::LowRankBandSolver(sparse, pairs, Eigen::VectorXd::Ones(n) - eps), eps);
  REQUIRE(ex.factored());

  TwoForms out;
  out.radiative = n;
  solver::ThermalNetwork net = test::emptyThermalNetwork(total);
  std::vector<std::tuple<int, int, double>> links;
  for (int i = 0; i + 1 < n; ++i)
    if ((i + 1) % 20 != 0) links.emplace_back(i, i + 1, 0.02);  // W/K along each cluster
  for (int i = 0; i < 10; ++i) links.emplace_back(box, i, 0.5);
  links.emplace_back(wall, 100, 1.0);
  test::setConductors(net, links);
  net.tabled_conductors.push_back({200, 201, {{200.0, 400.0}, {0.05, 0.5}}});
  net.capacitance.head(n) = 500.0 * c.area;  // J/K
  net.capacitance[box] = 2000.0;
  net.dissipation[box] = 5.0;
  net.fixed_temperature[wall] = 280.0;
  net.heaters.push_back({"box heater", box, box, 60.0, 195.0, 200.0});  // held at 195 K in the second position
  net.gr_space = Eigen::VectorXd::Zero(total);
  net.gr_space.head(n) = ex.gr_space;
  const double coupling = 0.05;  // m², box ↔ node 50

  out.dense = net;
  out.dense.gr = Eigen::MatrixXd::Zero(total, total);
  out.dense.gr.topLeftCorner(n, n) = ex.dense();
  out.dense.gr(box, 50) += coupling;
  out.dense.gr(50, box) += coupling;

  auto f = std::make_shared<solver::FactoredExchange>();
  std::vector<Eigen::Triplet<double>> d{{box, 50, coupling}, {50, box, coupling}};
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(ex.direct, i); it; ++it)
      d.emplace_back(static_cast<int>(i), static_cast<int>(it.col()), it.value());
  f->direct.resize(total, total);
  f->direct.setFromTriplets(d.begin(), d.end());
  f->basis = Eigen::MatrixXd::Zero(total, k);
  f->basis.topRows(n) = ex.basis;
  f->core = ex.core;
  out.factored = net;
  out.factored.gr.resize(0, 0);
  out.factored.gr_factored = f;
  return out;
}

// Built once for every test case here (its eigendecomposition is the slow part).
const TwoForms& forms() {
  static const TwoForms two = twoForms();
  return two;
}

// Loads of three positions: 0 … 40 W on each radiative node in sunlight, the third in
// eclipse (0 … 4 W: the planet's IR).
Eigen::MatrixXd loads(int total, int radiative) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 40.0);
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(total, 3);
  for (int p = 0; p < 3; ++p)
    for (int i = 0; i < radiative; ++i) q(i, p) = (p == 2 ? 0.1 : 1.0) * u(rng);
  return q;
}

double largest(const Eigen::MatrixXd& a) { return a.cwiseAbs().maxCoeff(); }

}  // namespace

TEST_CASE("factored GR: products, row sums, diagonal and the balance's spread agree with the dense GR") {
  const TwoForms& two = forms();
  const solver::FactoredExchange& f = *two.factored.gr_factored;
  const Eigen::MatrixXd& gr = two.dense.gr;
  const double scale = largest(gr);
  CHECK(largest(f.dense() - gr) <= 1e-12 * scale);  // the same products, summed in another order
  const Eigen::VectorXd x = Eigen::VectorXd::Random(gr.rows()).array() + 2.0;
  CHECK(largest(f.times(x) - gr * x) <= 1e-12 * scale * x.sum());
  CHECK(largest(f.rowSum() - gr.rowwise().sum()) <= 1e-12 * scale * gr.rows());
  CHECK(largest(f.diagonal() - gr.diagonal()) <= 1e-12 * scale);
  // Σ_j GR_ij |x_j − x_i|: exact over D, the reflected part bounded above by Cauchy–Schwarz
  // (R ≥ 0 here up to truncation) and below by the exact sum.
  Eigen::VectorXd exact = Eigen::VectorXd::Zero(gr.rows()), gross = exact;
  for (Eigen::Index j = 0; j < gr.cols(); ++j) {
    exact += gr.col(j).cwiseAbs().cwiseProduct((x.array() - x[j]).abs().matrix());
    gross += gr.col(j).cwiseAbs().cwiseProduct((x.array().abs() + std::abs(x[j])).matrix());
  }
  const Eigen::VectorXd spread = f.spread(x);
  // The rank's truncation leaves R slightly negative in places, so the bound may undershoot:
  // measured 0.98–1.10 of the exact sum here, against up to 15× for the gross exchange.
  const Eigen::ArrayXd ratio = spread.array() / exact.array();
  INFO("spread / exact " << ratio.minCoeff() << " … " << ratio.maxCoeff());
  CHECK(ratio.minCoeff() >= 0.95);
  CHECK(ratio.maxCoeff() <= 1.25);
  CHECK((spread.array() <= gross.array()).all());
  // A uniform x: nothing flows, and the bound says so.
  CHECK(largest(f.spread(Eigen::VectorXd::Constant(gr.rows(), 300.0))) <= 1e-9 * scale);
  // The Jacobian's diagonal (the uncertainty's past 3,000 nodes) without the matrix, both forms,
  // against the formed Jacobian's (conductors, the tabulated one's slope and 4σT³ GR).
  const Eigen::VectorXd t = 250.0 + 100.0 * (x.array() - 1.0);
  const Eigen::VectorXd reference = solver::netHeatJacobian(two.dense, t).diagonal();
  CHECK(largest(solver::netHeatJacobianDiagonal(two.dense, t) - reference) <= 1e-12 * largest(reference));
  CHECK(largest(solver::netHeatJacobianDiagonal(two.factored, t) - reference) <= 1e-10 * largest(reference));
}

TEST_CASE("steady states on the factored GR equal the dense LU's, with a controlled heater, a boundary node and tables") {
  const TwoForms& two = forms();
  const Eigen::Index total = two.dense.size();
  const Eigen::MatrixXd q = loads(static_cast<int>(total), two.radiative);
  solver::ThermalOptions opt;
  opt.tolerance_w = 1e-13;  // both Newtons to near round-off, so that they can be compared at 1e-9 K
  const solver::ThermalResult dense = solver::steadyStates(two.dense, q, opt);
  const solver::ThermalResult factored = solver::steadyStates(two.factored, q, opt);
  INFO(dense.message << " / " << factored.message);
  REQUIRE(dense.status == solver::Status::Converged);
  REQUIRE(factored.status == solver::Status::Converged);
  // The heater holds the box at its set point somewhere (its Jacobian rows are exercised).
  bool controlled = false;
  for (Eigen::Index p = 0; p < 3; ++p)
    controlled = controlled || (dense.heater_power(0, p) > 0 && dense.heater_power(0, p) < 60.0);
  CHECK(controlled);
  INFO("largest |ΔT| " << largest(dense.temperature - factored.temperature) << " K");
  // Temperatures of 100–300 K to 1e-10 K (measured 9e-14 K): 1e-12 relative, as the two GRs agree.
  CHECK(largest(dense.temperature - factored.temperature) <= 1e-10);
  CHECK(largest(dense.heater_power - factored.heater_power) <= 1e-9 * 60.0);
  // The heat flows from the factored GR balance like the dense ones.
  const solver::HeatFlows flows = solver::heatFlows(two.factored, factored, q);
  const solver::HeatFlows reference = solver::heatFlows(two.dense, dense, q);
  CHECK(largest(flows.radiative - reference.radiative) <= 1e-8 * largest(reference.radiative));
}

TEST_CASE("a transient on the factored GR equals the dense LU's") {
  const TwoForms& two = forms();
  const Eigen::Index total = two.dense.size();
  const Eigen::MatrixXd q = loads(static_cast<int>(total), two.radiative);
  solver::ThermalOptions opt;
  opt.tolerance_w = 1e-12;
  opt.max_step_s = 60.0;
  const std::vector<double> times{0.0, 1800.0, 3600.0};
  const Eigen::VectorXd initial = Eigen::VectorXd::Constant(total, 290.0);
  const solver::ThermalResult dense = solver::transient(two.dense, times, q, 5400.0, 1.0, initial, opt);
  const solver::ThermalResult factored = solver::transient(two.factored, times, q, 5400.0, 1.0, initial, opt);
  REQUIRE(dense.status == solver::Status::Converged);
  REQUIRE(factored.status == solver::Status::Converged);
  INFO("largest |ΔT| " << largest(dense.temperature - factored.temperature) << " K");
  // The same steps (the same heater switchings): what differs is each step's Newton residual,
  // 1e-12 of the flows, carried through ~100 steps (measured 4.5e-12 K; allowed 1e-9 K).
  CHECK(dense.heater_switches == factored.heater_switches);
  CHECK(largest(dense.temperature - factored.temperature) <= 1e-9);
}

TEST_CASE("factored GR: a node linked only through a reflector is determined, one linked to nothing is named") {
  // Nodes 0 and 1 never see each other (no direct part) but exchange by way of a reflector:
  // R = W K Wᵀ = 0.1 [[1, 1], [1, 1]] m². Node 0 sees space; node 1 does not.
  solver::ThermalNetwork net = test::emptyThermalNetwork(3);
  net.gr.resize(0, 0);
  auto f = std::make_shared<solver::FactoredExchange>();
  f->direct.resize(3, 3);
  f->basis = Eigen::MatrixXd::Zero(3, 1);
  f->basis(0, 0) = f->basis(1, 0) = 1.0;
  f->core = Eigen::MatrixXd::Constant(1, 1, 0.1);
  net.gr_factored = f;
  net.gr_space[0] = 0.5;
  // Node 2 has no link at all: undetermined in a steady state, as the dense form says too.
  CHECK(solver::undeterminedNodes(net, false) == std::vector<int>{2});
  solver::ThermalNetwork dense = net;
  dense.gr_factored = nullptr;
  dense.gr = f->dense();
  CHECK(solver::undeterminedNodes(dense, false) == std::vector<int>{2});
  // Without the reflector's link node 1 is alone too.
  auto none = std::make_shared<solver::FactoredExchange>(*f);
  none->core.setZero();
  net.gr_factored = none;
  CHECK(solver::undeterminedNodes(net, false) == std::vector<int>{1, 2});
}
