// The thermal engineer's model in the solver: stiff networks, thermostats, schedules,
// temperature tables, periodic transients and undetermined nodes, against closed forms
// and conservation.
#include "solver/thermal/temperatures.hpp"
#include "solver/units.hpp"
#include "thermal_support.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace radnet::solver;
using radnet::units::kStefanBoltzmann;
using radnet::test::setConductors;

namespace {

ThermalNetwork network(int n) { return radnet::test::emptyThermalNetwork(n); }

// Constant loads over a period with P evenly spaced samples.
ThermalForcing constantForcing(const ThermalNetwork& net, double period, int P) {
  ThermalForcing f;
  for (int p = 0; p < P; ++p) f.times_s.push_back(period * p / P);
  f.q_env = Eigen::MatrixXd::Zero(net.size(), P);
  f.load_period_s = f.schedule_period_s = period;
  return f;
}

// Largest |Σ of all heat flows| of every node and output time beyond what floating point
// resolves (HeatFlows::roundoff), relative to its largest term.
double relativeImbalance(const ThermalNetwork& net, const ThermalResult& r, const Eigen::MatrixXd& q_env) {
  const HeatFlows f = heatFlows(net, r, q_env);
  double worst = 0.0;
  for (Eigen::Index p = 0; p < q_env.cols(); ++p)
    for (Eigen::Index i = 0; i < q_env.rows(); ++i) {
      if (net.isFixed(i)) continue;
      const double terms[] = {q_env(i, p),       f.emitted(i, p), f.radiative(i, p), f.conducted(i, p),
                              f.dissipation(i, p), f.heater(i, p), f.stored(i, p)};
      double sum = 0, largest = 0;
      for (double x : terms) sum += x, largest = std::max(largest, std::abs(x));
      if (largest > 0) worst = std::max(worst, std::max(0.0, std::abs(sum) - f.roundoff(i, p)) / largest);
    }
  return worst;
}

}  // namespace

TEST_CASE("stiff network: conductances 1e-6 … 1e6 W/K in one model converge to the closed form") {
  // a —1e6 W/K— b (radiates, 1 m² black) —1e-6 W/K— c. a dissipates 100 W, b absorbs 500 W,
  // c dissipates 1e-5 W. All leaves through b: σ (T_b⁴ − 3⁴) = 600.00001 W;
  // T_a = T_b + 100/1e6 K, T_c = T_b + 1e-5/1e-6 = T_b + 10 K.
  ThermalNetwork net = network(3);
  net.gr_space[1] = 1.0;
  setConductors(net, {{0, 1, 1e6}, {1, 2, 1e-6}});
  net.dissipation << 100.0, 0.0, 1e-5;
  Eigen::MatrixXd q = Eigen::MatrixXd::Zero(3, 1);
  q(1, 0) = 500.0;
  const ThermalResult r = steadyStates(net, q);
  REQUIRE(r.status == Status::Converged);
  const double tb = std::pow(600.00001 / kStefanBoltzmann + 81.0, 0.25);
  // Newton's tolerance is 1e-9 of each node's flows: for a (1e6 W/K × 300 K through it) that
  // is 0.3 W, i.e. 3e-7 K of its 1e-4 K rise; c's flows are 3e-4 W, 3e-13 W → 3e-7 K. Allow 1e-6 K.
  CHECK(r.temperature(1, 0) == Approx(tb).margin(1e-6));
  CHECK(r.temperature(0, 0) - r.temperature(1, 0) == Approx(1e-4).margin(1e-6));
  CHECK(r.temperature(2, 0) - r.temperature(1, 0) == Approx(10.0).margin(1e-6));
}

TEST_CASE("stiff network: a transient with capacitances 0 … 1e6 J/K and a 30,000 W/K joint holds its steady state") {
  // A 2 mm aluminium panel, 1 m², front and back nodes: k A / t = 167 / 0.002 = 83,500 W/K;
  // a 1e6 J/K box on 1e-6 W/K; an arithmetic (C = 0) node between.
  ThermalNetwork net = network(4);
  net.gr_space << 0.85, 0.88, 0.0, 0.0;
  net.capacitance << 2421.0, 2421.0, 0.0, 1e6;
  setConductors(net, {{0, 1, 83500.0}, {1, 2, 2.0}, {2, 3, 1e-6}});
  net.dissipation << 0.0, 0.0, 5.0, 0.0;
  ThermalForcing f = constantForcing(net, 5400.0, 10);
  f.q_env.row(0).setConstant(600.0);
  const ThermalResult steady = steadyStates(net, f);
  REQUIRE(steady.status == Status::Converged);
  const Eigen::VectorXd start = steady.temperature.col(0);
  const ThermalResult tr = transient(net, f, 2.0, start);
  INFO(tr.message);
  REQUIRE(tr.status == Status::Converged);
  // From its own steady state nothing moves: within 1e-6 K (Newton's tolerance, summed over 1080 steps).
  CHECK((tr.temperature.colwise() - start).cwiseAbs().maxCoeff() < 1e-6);
  CHECK(relativeImbalance(net, tr, f.q_env) < 1e-6);
}

TEST_CASE("thermostat: a heated node on a conductor cycles inside its dead band with the analytic duty cycle") {
  // C = 1000 J/K on K = 1 W/K to 250 K; heater 50 W, on below 278.15 K, off above 283.15 K.
  // τ = C/K = 1000 s. On: T → 300 K, t_on = τ ln((300 − 278.15)/(300 − 283.15));
  // off: T → 250 K, t_off = τ ln((283.15 − 250)/(278.15 − 250)).
  ThermalNetwork net = network(2);
  net.capacitance << 1000.0, 0.0;
  setConductors(net, {{0, 1, 1.0}});
  net.fixed_temperature[1] = 250.0;
  net.heaters.push_back({"h", 0, 0, 50.0, 278.15, 283.15});
  const double t_on = 1000.0 * std::log(21.85 / 16.85), t_off = 1000.0 * std::log(33.15 / 28.15);
  const double cycle = t_on + t_off, duty = t_on / cycle;
  // A load period of exactly 10 cycles, so that the periodic state has whole cycles in it.
  ThermalForcing f = constantForcing(net, 10 * cycle, 400);
  Eigen::VectorXd initial(2);
  initial << 280.0, 250.0;
  for (double step : {10.0, 2.0}) {
    ThermalOptions opt;
    opt.max_step_s = step;
    const ThermalResult r = periodicTransient(net, f, initial, {1e-3, 20}, opt);
    REQUIRE(r.status == Status::Converged);
    INFO("time step " << step << " s, duty " << r.heater_duty[0] << " against " << duty);
    // Switching is located to 1e-3 K, i.e. 0.05 s of a 423 s cycle, and BDF2's error is
    // O(h²): the duty is within 1e-3 of the closed form at both steps (measured 1e-6).
    CHECK(r.heater_duty[0] == Approx(duty).margin(1e-3));
    // The sensor never leaves the band by more than the switching tolerance.
    CHECK(r.temperature.row(0).minCoeff() > 278.15 - 2e-3);
    CHECK(r.temperature.row(0).maxCoeff() < 283.15 + 2e-3);
    // Energy: over whole cycles the heater supplies what the conductor takes away.
    const double mean_conducted = (r.temperature.row(0).array() - 250.0).mean();
    CHECK(r.heater_duty[0] * 50.0 == Approx(mean_conducted).epsilon(0.02));  // sampled mean of T, 400 samples
    CHECK(relativeImbalance(net, r, f.q_env) < 1e-6);
  }
}

TEST_CASE("thermostat in a steady state: holds its sensor at on_below, or gives all it has, or stays off") {
  // A black 1 m² plate to space, 100 W absorbed: alone it sits at (100/σ + 3⁴)^¼ = 204.9 K.
  ThermalNetwork net = network(1);
  net.gr_space[0] = 1.0;
  const Eigen::MatrixXd q = Eigen::MatrixXd::Constant(1, 1, 100.0);
  auto run = [&](double power, double on_below) {
    net.heaters = {{"h", 0, 0, power, on_below, on_below + 5.0}};
    return steadyStates(net, q);
  };
  const ThermalResult held = run(500.0, 273.15);  // needs σ (273.15⁴ − 3⁴) − 100 = 215.6 W
  REQUIRE(held.status == Status::Converged);
  const double need = kStefanBoltzmann * (std::pow(273.15, 4) - 81.0) - 100.0;
  CHECK(held.temperature(0, 0) == Approx(273.15).margin(1e-9));
  CHECK(held.heater_power(0, 0) == Approx(need).epsilon(1e-9));
  CHECK(held.heater_duty[0] == Approx(need / 500.0).epsilon(1e-9));
  const ThermalResult short_of_power = run(100.0, 273.15);  // 200 W in all: (200/σ + 3⁴)^¼
  REQUIRE(short_of_power.status == Status::Converged);
  CHECK(short_of_power.heater_power(0, 0) == 100.0);
  // 1e-9 of the 200 W through it is 2e-7 W: 1e-8 K of 4σT³ ≈ 3.3 W/K, relative 5e-11; allow 1e-9.
  CHECK(short_of_power.temperature(0, 0) == Approx(std::pow(200.0 / kStefanBoltzmann + 81.0, 0.25)).epsilon(1e-9));
  const ThermalResult warm = run(100.0, 150.0);
  REQUIRE(warm.status == Status::Converged);
  CHECK(warm.heater_power(0, 0) == 0.0);
  CHECK(warm.temperature(0, 0) == Approx(std::pow(100.0 / kStefanBoltzmann + 81.0, 0.25)).epsilon(1e-9));
}

// Issue 38: a primary and a backup thermostat on one sensor failed every steady state below
// both set points as "singular Jacobian" (both held the sensor, at two temperatures).
TEST_CASE("two thermostats on one sensor in a steady state: the higher set point holds it, the other helps when it saturates") {
  // One node on K W/K to a 200 K boundary, no other load: holding T needs K (T − 200) W.
  ThermalNetwork net = network(2);
  net.fixed_temperature[1] = 200.0;
  const Eigen::MatrixXd q = Eigen::MatrixXd::Zero(2, 1);
  auto run = [&](double conductance, double backup_on_below) {
    setConductors(net, {{0, 1, conductance}});
    net.heaters = {{"primary", 0, 0, 10.0, 280.0, 285.0}, {"backup", 0, 0, 20.0, backup_on_below, backup_on_below + 5.0}};
    const ThermalResult r = steadyStates(net, q);
    REQUIRE(r.status == Status::Converged);
    return r;
  };
  // K = 0.1: the primary holds 280 K with 8 W; the backup (set at 270 K) stays off.
  const ThermalResult enough = run(0.1, 270.0);
  CHECK(enough.temperature(0, 0) == Approx(280.0).margin(1e-9));
  CHECK(enough.heater_power(0, 0) == Approx(8.0).epsilon(1e-9));
  CHECK(enough.heater_power(1, 0) == 0.0);
  // K = 0.2: 16 W would hold 280 K, the primary has 10 and saturates (250 K alone); the backup
  // then holds 270 K: 0.2 × 70 = 14 W in all, 4 W of it the backup's.
  const ThermalResult backup = run(0.2, 270.0);
  CHECK(backup.temperature(0, 0) == Approx(270.0).margin(1e-9));
  CHECK(backup.heater_power(0, 0) == 10.0);
  CHECK(backup.heater_power(1, 0) == Approx(4.0).epsilon(1e-9));
  // Listed the other way round (the backup's set point above the primary's): 290 K held by the
  // second heater, 18 W of its 20, the first off since 290 K is above its 280 K.
  const ThermalResult swapped = run(0.2, 290.0);
  CHECK(swapped.temperature(0, 0) == Approx(290.0).margin(1e-9));
  CHECK(swapped.heater_power(0, 0) == 0.0);
  CHECK(swapped.heater_power(1, 0) == Approx(18.0).epsilon(1e-9));
  // Equal set points: the first listed gives all its 10 W, the second the other 6 W.
  const ThermalResult equal = run(0.2, 280.0);
  CHECK(equal.temperature(0, 0) == Approx(280.0).margin(1e-9));
  CHECK(equal.heater_power(0, 0) == 10.0);
  CHECK(equal.heater_power(1, 0) == Approx(6.0).epsilon(1e-9));
}

TEST_CASE("schedules: a time table repeats each orbit and an illumination schedule follows the sunlit fraction") {
  DissipationSchedule table;
  table.kind = DissipationSchedule::Kind::Table;
  table.times_s = {0, 600, 900};
  table.power_w = {5, 20, 5};
  CHECK(table.at(0.0, 1, 1000) == 5.0);
  CHECK(table.at(599.0, 1, 1000) == 5.0);
  CHECK(table.at(600.0, 1, 1000) == 20.0);
  CHECK(table.at(1650.0, 1, 1000) == 20.0);  // the second orbit
  CHECK(table.at(1950.0, 1, 1000) == 5.0);
  DissipationSchedule light;
  light.kind = DissipationSchedule::Kind::Illumination;
  light.sunlit_w = 10.0;
  light.eclipse_w = 2.0;
  CHECK(light.at(0, 1.0, 0) == 10.0);
  CHECK(light.at(0, 0.0, 0) == 2.0);
  CHECK(light.at(0, 0.25, 0) == 4.0);  // penumbra: in proportion

  // A node on a conductor to 300 K, 1000 J/K, K = 1 W/K, heated by the table: in its last
  // orbit the temperature follows the piecewise exponentials, and every output balances.
  ThermalNetwork net = network(2);
  net.capacitance << 1000.0, 0.0;
  setConductors(net, {{0, 1, 1.0}});
  net.fixed_temperature[1] = 300.0;
  table.node = 0;
  net.schedules = {table};
  const ThermalForcing f = constantForcing(net, 1000.0, 20);
  const ThermalResult r = periodicTransient(net, f, Eigen::Vector2d(305.0, 300.0), {1e-6, 200});
  REQUIRE(r.status == Status::Converged);
  // Periodic solution of C dT/dt = Q(t) − K (T − 300), τ = 1000 s: u = T − 300 relaxes to Q/K
  // on each segment; the start value solves u₀ = periodic map(u₀).
  auto segment = [](double u, double q, double dt) { return q + (u - q) * std::exp(-dt / 1000.0); };
  const double a = std::exp(-1.0);  // the map is u₀ ↦ a u₀ + b
  const double b = segment(segment(segment(0.0, 5, 600), 20, 300), 5, 100);
  const double u0 = b / (1 - a);
  for (int p = 0; p < 20; ++p) {
    const double t = 50.0 * p;
    const double u = t <= 600 ? segment(u0, 5, t) : t <= 900 ? segment(segment(u0, 5, 600), 20, t - 600)
                                                             : segment(segment(segment(u0, 5, 600), 20, 300), 5, t - 900);
    // BDF2 with 10 s steps, restarted at each table entry: within 5e-3 K (measured 1e-3).
    CHECK(r.temperature(0, p) - 300.0 == Approx(u).margin(5e-3));
    CHECK(r.dissipation(0, p) == (t > 600 && t <= 900 ? 20.0 : 5.0));  // at an entry: the step that ended there
  }
  CHECK(relativeImbalance(net, r, f.q_env) < 1e-6);
}

TEST_CASE("tables: a conductor tabulated against the mean temperature, and a capacitance against temperature") {
  TemperatureTable k{{250.0, 350.0}, {0.4, 0.6}};
  CHECK(k.at(300.0) == Approx(0.5));
  CHECK(k.at(100.0) == 0.4);  // held beyond the ends
  CHECK(k.at(400.0) == 0.6);
  CHECK(k.slope(300.0) == Approx(0.002));
  CHECK(k.slope(400.0) == 0.0);
  // A free node with 20 W on a tabulated conductor to 300 K: (T − 300) K((T + 300)/2) = 20,
  // K(T̄) = 0.4 + 0.002 (T̄ − 250): solved by bisection.
  ThermalNetwork net = network(2);
  net.fixed_temperature[1] = 300.0;
  net.dissipation[0] = 20.0;
  net.tabled_conductors.push_back({0, 1, k});
  const ThermalResult r = steadyStates(net, Eigen::MatrixXd::Zero(2, 1));
  REQUIRE(r.status == Status::Converged);
  auto g = [&](double t) { return (t - 300) * k.at(0.5 * (t + 300)) - 20.0; };
  double lo = 300, hi = 400;
  for (int it = 0; it < 200; ++it) (g(0.5 * (lo + hi)) < 0 ? lo : hi) = 0.5 * (lo + hi);
  CHECK(r.temperature(0, 0) == Approx(lo).epsilon(1e-9));  // Newton's 1e-9 of the 20 W through it
  // Capacitance C(T) = 100 + 2 T J/K heated by 50 W with no losses: the energy
  // 100 T + T² rises at 50 W, T(t) = −50 + √((50 + T₀)² + 50 t).
  ThermalNetwork cap = network(1);
  cap.capacitance_tables.emplace_back(0, TemperatureTable{{100.0, 600.0}, {300.0, 1300.0}});
  cap.dissipation[0] = 50.0;
  ThermalForcing f;
  f.times_s = {0, 500, 1000};
  f.q_env = Eigen::MatrixXd::Zero(1, 3);
  const ThermalResult heat = transient(cap, f, 1.0, Eigen::VectorXd::Constant(1, 200.0));
  REQUIRE(heat.status == Status::Converged);
  for (int p = 0; p < 3; ++p)  // BDF2 at 10 s steps on a smooth solution: within 1e-4 K (measured 1e-6)
    CHECK(heat.temperature(0, p) == Approx(-50.0 + std::sqrt(250.0 * 250.0 + 50.0 * f.times_s[p])).margin(1e-4));
}

TEST_CASE("periodic transient: stops when orbits repeat, and a restart from the periodic state changes nothing") {
  // A node of 5000 J/K on 1 W/K to 250 K, a sinusoidal load over a 6000 s orbit: the
  // orbit-to-orbit change decays by exp(−6000/5000) = 0.30 per orbit.
  ThermalNetwork net = network(2);
  net.capacitance << 5000.0, 0.0;
  setConductors(net, {{0, 1, 1.0}});
  net.fixed_temperature[1] = 250.0;
  ThermalForcing f = constantForcing(net, 6000.0, 60);
  for (int p = 0; p < 60; ++p) f.q_env(0, p) = 20.0 + 20.0 * std::sin(2 * M_PI * p / 60.0);
  const Eigen::Vector2d initial(300.0, 250.0);
  const ThermalResult r = periodicTransient(net, f, initial, {0.01, 50});
  REQUIRE(r.status == Status::Converged);
  CHECK(r.periodic_residual_k <= 0.01);
  // From 50 K off the periodic mean, 50 · 0.30ⁿ < 0.01 needs n ≥ 8 orbit-to-orbit changes.
  CHECK(r.orbits >= 8);
  CHECK(r.orbits <= 12);
  // The periodic state, started again (position 0 is the orbit's start), repeats itself.
  const ThermalResult again = transient(net, f, 1.0, r.temperature.col(0));
  REQUIRE(again.status == Status::Converged);
  CHECK((again.temperature - r.temperature).cwiseAbs().maxCoeff() < 0.01);
  // Too few orbits allowed: an error that says by how much.
  const ThermalResult short_run = periodicTransient(net, f, initial, {0.01, 3});
  CHECK(short_run.status == Status::NotConverged);
  CHECK(short_run.message.find("did not become periodic") != std::string::npos);
  // The nodes still changing most, largest first: their changes are the residual's parts.
  REQUIRE_FALSE(short_run.worst_changes.empty());
  CHECK(short_run.worst_changes.front().second == Approx(short_run.periodic_residual_k));
  for (size_t k = 1; k < short_run.worst_changes.size(); ++k)
    CHECK(short_run.worst_changes[k].second <= short_run.worst_changes[k - 1].second);
}

TEST_CASE("undetermined temperatures: an isolated or sealed group with nothing to fix its level is named") {
  ThermalNetwork net = network(5);
  net.gr_space[0] = 1.0;
  setConductors(net, {{0, 1, 1.0}, {2, 3, 5.0}});  // 0–1 reach space; 2–3 sealed together; 4 alone
  net.gr(2, 3) = net.gr(3, 2) = 0.1;
  CHECK(undeterminedNodes(net, false) == std::vector<int>{2, 3, 4});
  net.capacitance[3] = 100.0;  // a transient fixes the sealed pair's level by its heat content
  CHECK(undeterminedNodes(net, true) == std::vector<int>{4});
  net.fixed_temperature[4] = 300.0;
  CHECK(undeterminedNodes(net, true).empty());
  // A strap of 1e-6 W/K beside a 1e6 W/K joint still counts as a link.
  ThermalNetwork strap = network(3);
  strap.gr_space[0] = 1.0;
  setConductors(strap, {{0, 1, 1e6}, {1, 2, 1e-6}});
  CHECK(undeterminedNodes(strap, false).empty());
}

TEST_CASE("forcing: loads and sunlit fraction linear between samples, wrapping with the period or held") {
  ThermalForcing f;
  f.times_s = {0.0, 100.0, 300.0};
  f.q_env = Eigen::MatrixXd(1, 3);
  f.q_env << 10.0, 20.0, 40.0;
  f.sunlit_fraction = {1.0, 0.0, 0.5};
  f.load_period_s = 400.0;
  CHECK(f.loadAt(50.0)[0] == Approx(15.0));
  CHECK(f.loadAt(200.0)[0] == Approx(30.0));
  CHECK(f.loadAt(350.0)[0] == Approx(25.0));  // between the last sample and the first of the next period
  CHECK(f.loadAt(850.0)[0] == Approx(15.0));  // the third period
  CHECK(f.sunlitAt(50.0) == Approx(0.5));
  CHECK(f.sunlitAt(350.0) == Approx(0.75));
  f.load_period_s = 0.0;  // no period: held beyond the ends
  CHECK(f.loadAt(-5.0)[0] == 10.0);
  CHECK(f.loadAt(1e6)[0] == 40.0);
  CHECK(f.sunlitAt(1e6) == 0.5);
}

TEST_CASE("a Newton that does not converge names the node furthest from balance") {
  // Node 0 (1,000 W) radiates mostly through node 1; node 2 hangs on a weak strap. One
  // iteration from the starting guess balances nothing to 1e-9: a node is named (the one
  // furthest from its tolerance, relative to its own flows).
  ThermalNetwork net = network(3);
  net.gr_space << 0.05, 1.0, 0.0;
  net.gr(0, 1) = net.gr(1, 0) = 0.5;  // node 0 radiates mostly through node 1
  setConductors(net, {{1, 2, 0.01}});
  net.capacitance_tables.push_back({0, TemperatureTable{{100.0, 1000.0}, {1.0, 2.0}}});  // unused in steady states
  net.dissipation << 1000.0, 1e-3, 0.0;
  ThermalOptions opt;
  opt.max_newton_iterations = 1;
  const ThermalResult r = steadyStates(net, Eigen::MatrixXd::Zero(3, 1), opt);
  REQUIRE(r.status == Status::NotConverged);
  CHECK(r.failed_node >= 0);  // the node with the largest residual relative to its own flows
  CHECK(r.failed_node < 3);
  // With its iterations, the same network converges and names nothing.
  const ThermalResult ok = steadyStates(net, Eigen::MatrixXd::Zero(3, 1));
  CHECK(ok.status == Status::Converged);
  CHECK(ok.failed_node == -1);
}
