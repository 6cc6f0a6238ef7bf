// Temperatures: steady states and transients against closed forms and a bisection.
#include "solver/radiative/network.hpp"
#include "solver/thermal/temperatures.hpp"
#include "thermal_support.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <vector>

using namespace radnet::solver;

namespace {

ThermalNetwork emptyNetwork(int n) { return radnet::test::emptyThermalNetwork(n); }

// Adds a conductor of k W/K between i and j to those the network has.
void link(ThermalNetwork& net, int i, int j, double k) {
  std::vector<std::tuple<int, int, double>> links;
  for (int a = 0; a < net.conductors.outerSize(); ++a)
    for (Eigen::SparseMatrix<double>::InnerIterator it(net.conductors, a); it; ++it)
      if (it.row() < it.col()) links.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
  links.emplace_back(i, j, k);
  radnet::test::setConductors(net, links);
}

}  // namespace

TEST_CASE("steady state: a plate facing the Sun, α S A = ε σ A (T⁴ − T_space⁴)") {
  ThermalNetwork net = emptyNetwork(1);
  const double alpha = 0.92, eps = 0.85, area = 2.0, S = 1361.0;
  net.gr_space[0] = eps * area;
  const ThermalResult r = steadyStates(net, Eigen::MatrixXd::Constant(1, 1, alpha * S * area));
  REQUIRE(r.status == Status::Converged);
  const double exact = std::pow(alpha * S / (eps * kStefanBoltzmann) + std::pow(3.0, 4), 0.25);
  CHECK(r.temperature(0, 0) == Approx(exact).epsilon(1e-12));
}

TEST_CASE("steady state: radiation and conduction between boundary nodes, against bisection") {
  // a fixed at 400 K, b free, c fixed at 300 K; infinite plates a–b (ε 0.8, 0.5), K(b, c) = 3 W/K.
  ThermalNetwork net = emptyNetwork(3);
  const double gr = 1.0 / (1 / 0.8 + 1 / 0.5 - 1);
  net.gr(0, 1) = net.gr(1, 0) = gr;
  link(net, 1, 2, 3.0);
  net.fixed_temperature[0] = 400.0;
  net.fixed_temperature[2] = 300.0;
  const ThermalResult r = steadyStates(net, Eigen::MatrixXd::Zero(3, 1));
  REQUIRE(r.status == Status::Converged);
  auto f = [&](double t) { return kStefanBoltzmann * gr * (std::pow(400.0, 4) - std::pow(t, 4)) + 3.0 * (300.0 - t); };
  double lo = 300, hi = 400;
  for (int k = 0; k < 200; ++k) (f(0.5 * (lo + hi)) > 0 ? lo : hi) = 0.5 * (lo + hi);
  // Newton (with chord steps) stops at 1e-9 of the node's flows, ~400 W here: 4e-7 W, i.e.
  // 4e-8 K of 4σT³ ≈ 11 W/K, a relative 1e-10 of the temperature.
  CHECK(r.temperature(1, 0) == Approx(0.5 * (lo + hi)).epsilon(1e-9));
  CHECK(r.temperature(0, 0) == 400.0);
  CHECK(r.temperature(2, 0) == 300.0);
}

TEST_CASE("steady state from 3 K to 2000 K in one network") {
  ThermalNetwork net = emptyNetwork(2);
  net.gr_space << 1.0, 1.0;
  net.dissipation << kStefanBoltzmann * std::pow(2000.0, 4), 0.0;  // 907 kW: node 0 at 2000 K
  const ThermalResult r = steadyStates(net, Eigen::MatrixXd::Zero(2, 1));
  REQUIRE(r.status == Status::Converged);
  CHECK(r.temperature(0, 0) == Approx(std::pow(std::pow(2000.0, 4) + std::pow(3.0, 4), 0.25)).epsilon(1e-12));
  CHECK(r.temperature(1, 0) == Approx(3.0).epsilon(1e-9));  // nothing but space: space temperature
}

TEST_CASE("transient: conduction to a boundary decays as exp(−K t / C) (BDF2, 10 s steps)") {
  ThermalNetwork net = emptyNetwork(2);
  net.capacitance << 1000.0, 0.0;
  link(net, 0, 1, 2.0);
  net.fixed_temperature[1] = 300.0;
  std::vector<double> times;
  for (int k = 0; k < 10; ++k) times.push_back(100.0 * k);
  Eigen::VectorXd initial(2);
  initial << 400.0, 300.0;
  const ThermalResult r = transient(net, times, Eigen::MatrixXd::Zero(2, 10), 1000.0, 1.0, initial);
  REQUIRE(r.status == Status::Converged);
  // τ = C/K = 500 s; second-order BDF2 at h/τ = 0.02 is 5e-3 K off at most here
  // (measured; the O(h²) global error): allow 0.01 K.
  for (int k = 0; k < 10; ++k)
    CHECK(r.temperature(0, k) == Approx(300.0 + 100.0 * std::exp(-times[k] / 500.0)).margin(0.01));
}

TEST_CASE("transient: many orbits of a constant load settle at the steady state") {
  ThermalNetwork net = emptyNetwork(2);
  net.gr_space << 0.5, 0.2;
  net.gr(0, 1) = net.gr(1, 0) = 0.1;
  net.capacitance << 500.0, 0.0;  // node 1 arithmetic (no capacitance)
  link(net, 0, 1, 0.5);
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(2, 4);
  q.row(0).setConstant(300.0);
  const std::vector<double> times = {0, 1500, 3000, 4500};
  const ThermalResult steady = steadyStates(net, q.col(0));
  const ThermalResult tr = transient(net, times, q, 6000.0, 20.0, Eigen::VectorXd::Constant(2, 250.0));
  REQUIRE(tr.status == Status::Converged);
  CHECK(tr.temperature(0, 3) == Approx(steady.temperature(0, 0)).epsilon(1e-6));
  CHECK(tr.temperature(1, 3) == Approx(steady.temperature(1, 0)).epsilon(1e-6));
}

TEST_CASE("thermal: a node with no link at all is reported, never NaN") {
  ThermalNetwork net = emptyNetwork(1);  // no radiation, no conductor, no capacitance
  net.dissipation[0] = 5.0;
  const ThermalResult r = steadyStates(net, Eigen::MatrixXd::Zero(1, 1));
  CHECK(r.status != Status::Converged);
  CHECK_FALSE(r.message.empty());
}

TEST_CASE("heat flows: a node cooling through a conductor stores −C dT/dt = K (T − T_b), the boundary supplies it") {
  ThermalNetwork net = emptyNetwork(2);
  net.capacitance << 1000.0, 0.0;
  link(net, 0, 1, 2.0);
  net.fixed_temperature[1] = 300.0;
  std::vector<double> times;
  for (int k = 0; k < 10; ++k) times.push_back(100.0 * k);
  Eigen::VectorXd initial(2);
  initial << 400.0, 300.0;
  const Eigen::MatrixXd q = Eigen::MatrixXd::Zero(2, 10);
  const ThermalResult r = transient(net, times, q, 1000.0, 1.0, initial);
  REQUIRE(r.status == Status::Converged);
  const HeatFlows f = heatFlows(net, r, q);
  for (int k = 1; k < 10; ++k) {
    // Analytic: T = 300 + 100 e^{−t/τ}, τ = 500 s, so −C dT/dt = 2 · 100 e^{−t/τ} W flows out of
    // storage into the conductor. The BDF2 derivative carries the scheme's O(h²) error: the
    // temperatures are within 5e-3 K (test above), i.e. 0.01 W of conducted power; allow 0.05 W.
    const double exact = 200.0 * std::exp(-times[static_cast<size_t>(k)] / 500.0);
    CHECK(f.stored(0, k) == Approx(exact).margin(0.05));
    CHECK(f.conducted(0, k) == Approx(-exact).margin(0.05));
    // Node 0 balances to Newton's tolerance; node 1 (fixed) gets what the conductor brings.
    CHECK(std::abs(f.stored(0, k) + f.conducted(0, k)) < 1e-6);
    CHECK(f.boundary(1, k) == Approx(-f.conducted(1, k)).margin(1e-12));
    CHECK(f.conducted(1, k) == Approx(-f.conducted(0, k)).margin(1e-9));
    CHECK(f.stored(1, k) == 0.0);
  }
}

TEST_CASE("heat flows: a sunlit plate in a steady state emits what it absorbs, σ GR_space (T⁴ − T_space⁴)") {
  ThermalNetwork net = emptyNetwork(1);
  const double eps = 0.8, area = 0.5, absorbed = 300.0;
  net.gr_space << eps * area;
  net.dissipation << 20.0;
  const Eigen::MatrixXd q = Eigen::MatrixXd::Constant(1, 1, absorbed);
  const ThermalResult r = steadyStates(net, q);
  REQUIRE(r.status == Status::Converged);
  const HeatFlows f = heatFlows(net, r, q);
  const double t = r.temperature(0, 0);
  CHECK(f.emitted(0, 0) == Approx(-kStefanBoltzmann * eps * area * (std::pow(t, 4) - std::pow(3.0, 4))).epsilon(1e-14));
  CHECK(f.emitted(0, 0) == Approx(-(absorbed + 20.0)).epsilon(1e-9));  // Newton's relative tolerance
  CHECK(f.dissipation(0, 0) == 20.0);
  CHECK(f.stored(0, 0) == 0.0);
  CHECK(f.radiative(0, 0) == 0.0);
}

TEST_CASE("progress: every output of every orbit reported once and in order, steady states as one orbit") {
  ThermalNetwork net = emptyNetwork(2);
  net.gr_space << 0.5, 0.2;
  net.gr(0, 1) = net.gr(1, 0) = 0.1;
  net.capacitance << 500.0, 100.0;
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(2, 4);
  q.row(0).setConstant(300.0);
  const std::vector<double> times = {0, 1500, 3000, 4500};
  std::vector<std::array<int, 3>> calls;
  ThermalOptions opt;
  opt.progress = [&calls](int orbit, int done, int outputs) { calls.push_back({orbit, done, outputs}); };
  REQUIRE(transient(net, times, q, 6000.0, 3.0, Eigen::VectorXd::Constant(2, 250.0), opt).status == Status::Converged);
  REQUIRE(calls.size() == 12);
  for (size_t k = 0; k < calls.size(); ++k) CHECK(calls[k] == std::array<int, 3>{int(k / 4) + 1, int(k % 4) + 1, 4});
  calls.clear();
  ThermalForcing forcing;
  forcing.times_s = times, forcing.q_env = q;
  REQUIRE(steadyStates(net, forcing, opt).status == Status::Converged);
  REQUIRE(calls.size() == 4);
  CHECK(calls.back() == std::array<int, 3>{1, 4, 4});
}
