// Thermal solves on networks of a spacecraft's size: a two-sided aluminium panel of N × N
// cells (2N² nodes: in-plane and through-thickness conductors from the shell formulas, GR
// between neighbouring cells and to space), orbit loads over 40 positions. Times steady
// states per position and a one-orbit BDF2 transient with chord steps on a cached LU
// against a new LU every Newton iteration, in the same run; writes a Markdown table.
#include "solver/thermal/temperatures.hpp"
#include "solver/units.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>

using namespace radnet::solver;

namespace {

// A 1 × 1 m panel of 2 mm aluminium in N × N cells of a = 1/N m, a front (cells, ε 0.85)
// and a back (paint, ε 0.88) node each.
ThermalNetwork panel(int cells, unsigned seed) {
  const int n = 2 * cells * cells;
  const double a = 1.0 / cells, area = a * a, k = 167.0, t = 0.002, rho_c = 2700.0 * 896.0;
  ThermalNetwork net;
  net.gr = Eigen::MatrixXd::Zero(n, n);
  net.gr_space = Eigen::VectorXd::Zero(n);
  net.capacitance = Eigen::VectorXd::Constant(n, 0.5 * rho_c * t * area);
  net.dissipation = Eigen::VectorXd::Zero(n);
  net.fixed_temperature = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Eigen::Triplet<double>> links;
  auto id = [&](int i, int j, int side) { return 2 * (i * cells + j) + side; };
  for (int i = 0; i < cells; ++i)
    for (int j = 0; j < cells; ++j)
      for (int side = 0; side < 2; ++side) {
        const int p = id(i, j, side);
        if (side == 0) links.emplace_back(p, p + 1, k * area / t), links.emplace_back(p + 1, p, k * area / t);
        for (const auto& [di, dj] : {std::pair{1, 0}, std::pair{0, 1}})
          if (i + di < cells && j + dj < cells) {
            const int q = id(i + di, j + dj, side);
            links.emplace_back(p, q, k * 0.5 * t), links.emplace_back(q, p, k * 0.5 * t);  // k (t/2) L/d, L = d
          }
        // The front sees the bus and other cells a little (a dense GR), both sides see space.
        net.gr_space[p] = (side == 0 ? 0.85 : 0.88) * area * 0.97;
      }
  for (int p = 0; p < n; p += 2)
    for (int q = p + 2; q < n; q += 2) net.gr(p, q) = net.gr(q, p) = 0.03 * area * area * u(rng) * 2.0 / n * 1e2;
  net.conductors.resize(n, n);
  net.conductors.setFromTriplets(links.begin(), links.end());
  return net;
}

// Sunlit fronts with a cosine over the orbit and 36 % eclipse; backs see albedo and Earth IR.
ThermalForcing orbitLoads(const ThermalNetwork& net, double period) {
  ThermalForcing f;
  const int P = 40;
  f.q_env.resize(net.size(), P);
  for (int p = 0; p < P; ++p) {
    const double phase = 2 * M_PI * p / P;
    f.times_s.push_back(period * p / P);
    const double sun = std::cos(phase) > -0.42 ? 1361.0 * 0.92 * std::max(0.2, std::cos(0.5 * phase)) : 0.0;
    for (Eigen::Index i = 0; i < net.size(); ++i)
      f.q_env(i, p) = (i % 2 == 0 ? sun : 237.0 * 0.88 * 0.6) * net.gr_space[i] / 0.85;
  }
  f.load_period_s = f.schedule_period_s = period;
  return f;
}

struct Timed {
  ThermalResult r;
  double seconds;
};

template <class F>
Timed timed(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  ThermalResult r = f();
  return {std::move(r), std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()};
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out_path = argc > 1 ? argv[1] : "thermal-benchmark.md";
  std::ostringstream md;
  md << std::setprecision(3);
  md << "# Thermal solve benchmark\n\n"
     << "`bench/bench_thermal` (`make bench`): a two-sided 2 mm aluminium panel of N × N cells\n"
     << "(2N² nodes; shell conductors k t/2 L/d in plane and k A/t = 83,500 W/K · A/1 m² through\n"
     << "the thickness; a dense GR among the fronts; 40 orbit positions, 5,400 s orbit). Steady\n"
     << "states at every position, and a one-orbit transient (BDF2, 30 s steps), each with chord\n"
     << "steps on a cached LU (`reuse_jacobian`, the default) and with a new LU every Newton\n"
     << "iteration, in the same run. Δ: the largest temperature difference between the two.\n"
     << "One thread (Eigen without a threaded BLAS); Debian 12, 2 cores.\n\n"
     << "| nodes | solve | new LU each iteration: s (iterations, LUs) | cached LU: s (iterations, LUs) | speed-up | Δ K |\n"
     << "|---|---|---|---|---|---|\n";
  for (int cells : {10, 20, 32}) {
    const ThermalNetwork net = panel(cells, 7);
    const ThermalForcing f = orbitLoads(net, 5400.0);
    const Eigen::VectorXd initial = Eigen::VectorXd::Constant(net.size(), 290.0);
    for (const bool transient : {false, true}) {
      ThermalOptions fresh, chord;
      fresh.reuse_jacobian = false;
      fresh.max_step_s = chord.max_step_s = 30.0;
      auto run = [&](const ThermalOptions& o) {
        return timed([&] { return transient ? radnet::solver::transient(net, f, 1.0, initial, o) : steadyStates(net, f, o); });
      };
      const Timed a = run(fresh), b = run(chord);
      if (a.r.status != Status::Converged || b.r.status != Status::Converged) {
        std::cerr << "bench_thermal: not converged: " << a.r.message << " / " << b.r.message << "\n";
        return 3;
      }
      md << "| " << net.size() << " | " << (transient ? "transient, 1 orbit" : "steady, 40 positions") << " | "
         << a.seconds << " (" << a.r.newton_iterations << ", " << a.r.factorisations << ") | " << b.seconds << " ("
         << b.r.newton_iterations << ", " << b.r.factorisations << ") | " << a.seconds / b.seconds << "× | "
         << (a.r.temperature - b.r.temperature).cwiseAbs().maxCoeff() << " |\n";
      std::cerr << "bench_thermal: " << net.size() << " nodes done\n";
    }
  }
  std::ofstream(out_path) << md.str();
  std::cout << md.str();
  return 0;
}
