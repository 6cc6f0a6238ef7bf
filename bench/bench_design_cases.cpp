// What a design case costs on the one eigendecomposition (docs/design-cases-benchmark.md):
// on the 1,602-node satellite with hot and cold cases (bench/cases/satellite-1602-design.yaml),
//  1. one more optical set, radiative part: its two k×k band cores and every position's band
//     solves, against a full re-solve with a dense LU of (I − S F) per band, in the same run,
//     both giving the absorbed power of all positions (their difference is reported);
//  2. the rest of an optical set: its exchange factors GR (solver policy) and temperatures;
//  3. 64 samples of α and ε on the one decomposition, against 64 separate full runs (the
//     run is timed three times; 64 × its median).
// Usage: bench_design_cases <case.yaml> <out.md>
#include "bench_support.hpp"
#include "cases/config/case_file.hpp"
#include "cases/pipeline/design_run.hpp"
#include "cases/pipeline/geometry_run.hpp"
#include "cases/pipeline/orbit_sweep.hpp"
#include "solver/policy.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

using namespace radnet;
using radnet::bench::since;
using Clock = std::chrono::steady_clock;

namespace {

// The absorbed power of all positions by one dense LU of (I − S F) per band: M = (I − S F)⁻¹ S E,
// H = F M, absorbed (1 − ρ) A (E + H).
Eigen::MatrixXd denseLuAbsorbed(const solver::Network& net, const cases::OpticalSet& set,
                                const orbits::EnvironmentLoads& e) {
  const Eigen::MatrixXd f = net.viewFactors();
  const Eigen::Index n = f.rows(), P = e.direct.cols();
  auto band = [&](const Eigen::VectorXd& rho, const Eigen::MatrixXd& irradiance) {
    const Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n) - rho.asDiagonal() * f;
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
    const Eigen::MatrixXd m = lu.solve(rho.asDiagonal() * irradiance);
    return Eigen::MatrixXd((Eigen::VectorXd::Ones(n) - rho).cwiseProduct(net.area()).asDiagonal() *
                           (irradiance + f * m));
  };
  Eigen::MatrixXd solar_in(n, 2 * P);
  solar_in << e.direct, e.albedo;
  const Eigen::MatrixXd solar = band(Eigen::VectorXd::Ones(n) - set.absorptivity, solar_in);
  return solar.leftCols(P) + solar.rightCols(P) + band(Eigen::VectorXd::Ones(n) - set.emissivity, e.earth_ir);
}

std::string machine() {
  std::ifstream cpu("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  int cores = 0;
  while (std::getline(cpu, line)) {
    if (line.rfind("model name", 0) == 0 && model == "unknown CPU") model = line.substr(line.find(':') + 2);
    if (line.rfind("processor", 0) == 0) ++cores;
  }
  return model + ", " + std::to_string(cores) + " cores";
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: bench_design_cases <case.yaml> <out.md>\n";
    return 2;
  }
  std::ostringstream quiet;
  cases::LoadedCase loaded = cases::loadCase(argv[1]);
  cases::GeometryCase& c = *loaded.geometry;
  const auto sampling = c.optical_uncertainty;
  c.optical_uncertainty.reset();
  // A full run (both design cases, no sampling), three times.
  std::vector<double> full;
  cases::GeometryRunResult r;
  for (int k = 0; k < 3; ++k) {
    const auto t0 = Clock::now();
    r = cases::runGeometryCase(c, false, quiet);
    full.push_back(since(t0));
  }
  std::sort(full.begin(), full.end());
  const solver::Network& net = *r.radiative.network;
  const int n = net.size();
  const cases::OpticalSet& eol = c.optical_sets.back();
  const orbits::EnvironmentLoads& e = r.sweep->irradiance;
  const int P = static_cast<int>(e.direct.cols());

  // 1. One more optical set: cores and band solves against a dense LU per band.
  auto t0 = Clock::now();
  const cases::BandCores cores = cases::bandCores(r.radiative, eol);
  const double t_cores = since(t0);
  t0 = Clock::now();
  const Eigen::MatrixXd q_core = cases::absorbedPower(*cores.solar, *cores.ir, net, e, r.solver.refineTolerance());
  const double t_solves = since(t0);
  t0 = Clock::now();
  const Eigen::MatrixXd q_lu = denseLuAbsorbed(net, eol, e);
  const double t_lu = since(t0);
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    const double scale = q_lu.row(i).cwiseAbs().maxCoeff();
    if (scale > 0) worst = std::max(worst, (q_core.row(i) - q_lu.row(i)).cwiseAbs().maxCoeff() / scale);
  }
  // 2. Its exchange factors by the policy.
  t0 = Clock::now();
  const solver::ExchangeFactors ex = solver::policy::exchangeFactors(net, r.radiative.pairs, eol.emissivity, r.solver);
  const double t_gr = since(t0);
  double t_eigen = 0.0, t_thermal = 0.0;
  for (const auto& [stage, s] : r.timings.entries()) {
    if (stage == cases::Stage::Eigendecomposition) t_eigen = s;
    if (stage == cases::Stage::Thermal) t_thermal = s;
  }
  // 3. 64 samples on the one decomposition.
  c.optical_uncertainty = sampling;
  c.optical_uncertainty->samples = 64;
  const cases::GeometryRunResult ru = cases::runGeometryCase(c, false, quiet);
  const double t_samples = ru.optical_uncertainty->sample_seconds;

  std::ofstream md(argv[2]);
  md << std::setprecision(3);
  md << "# Design cases on one eigendecomposition\n\n"
     << "Measured by `make bench` (`build/bench/bench_design_cases " << argv[1] << "`) on " << machine()
     << ", one process; " << n << " nodes, rank " << r.radiative.pairs.rank() << ", " << P
     << " positions over the two design cases (hot: EOL optics; cold: BOL), solver tolerance "
     << r.solver.refineTolerance() << ".\n\n"
     << "## One more optical set\n\n"
     << "| step | s |\n|---|---|\n"
     << "| two k×k band cores | " << t_cores << " |\n"
     << "| band solves of every position (3 × " << P << " right-hand sides, refined with the full G) | " << t_solves
     << " |\n"
     << "| **radiative part on the decomposition** | **" << t_cores + t_solves << "** |\n"
     << "| the same by a dense LU of (I − S F) per band | " << t_lu << " |\n"
     << "| ratio | **" << t_lu / (t_cores + t_solves) << "×** |\n"
     << "| exchange factors GR (" << ex.method << ", the solver policy) | " << t_gr << " |\n"
     << "| temperatures of both cases (steady per position) | " << t_thermal << " |\n"
     << "| a new eigendecomposition (what it does not cost) | " << t_eigen << " |\n\n"
     << "The two answers differ by at most " << worst
     << " of a node's orbit-maximum absorbed power (the refinement tolerance).\n\n"
     << "## 64 samples of α and ε\n\n"
     << "| | s |\n|---|---|\n"
     << "| one full run of both cases (median of 3) | " << full[1] << " |\n"
     << "| 64 separate full runs (64 × that) | " << 64 * full[1] << " |\n"
     << "| 64 samples on the one decomposition | " << t_samples << " |\n"
     << "| ratio | **" << 64 * full[1] / t_samples << "×** |\n\n"
     << "A sample costs the cores, band solves and GR of each optical set a case uses, and the "
     << "temperatures of every case; view factors, loads and the decomposition are not redone.\n";
  std::cout << "one optical set: " << t_cores + t_solves << " s on the decomposition, " << t_lu
            << " s by dense LU; 64 samples " << t_samples << " s against " << 64 * full[1] << " s\n";
  return 0;
}
