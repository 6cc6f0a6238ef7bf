// What a design case costs on the one eigendecomposition (docs/design-cases-benchmark.md):
// on the 1,602-node satellite with hot and cold cases (bench/cases/satellite-1602-design.yaml),
//  1. one more optical set, radiative part: its two k×k band cores and every position's band
//     solves, against a full re-solve with a dense LU of (I − S F) per band, in the same run,
//     both giving the absorbed power of all positions (their difference is reported);
//  2. the rest of an optical set: its exchange factors GR (solver policy) and temperatures;
//  3. 64 samples of α and ε on the one decomposition, against 64 separate full runs (the
//     run is timed three times; 64 × its median).
// Part 1 is repeated on a larger model (its own optics with α + 0.15 and ε − 0.05 as the
// extra set) when one is given: the LU grows as n³, the cores as n k².
// Usage: bench_design_cases <design-case.yaml> <out.md> [<larger-case.yaml>]
#include "bench_support.hpp"
#include "cases/config/case_file.hpp"
#include "cases/pipeline/design_run.hpp"
#include "cases/pipeline/geometry_run.hpp"
#include "cases/pipeline/orbit_sweep.hpp"
#include "solver/radiative/policy.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
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

// Part 1 on a run: the extra optical set's cores and band solves against a dense LU per band.
struct OpticalSetCost {
  int n = 0, rank = 0, positions = 0;
  double cores_s = 0, solves_s = 0, lu_s = 0, gr_s = 0, eigen_s = 0, worst = 0;
  double unrefined_s = 0, unrefined_worst = 0;  ///< the rank-k answer without refinement
  std::string gr_method;
};

OpticalSetCost opticalSetCost(const cases::GeometryRunResult& r, const cases::OpticalSet& set) {
  // One core for both sides: radnet_solver is built without OpenMP, while this file's
  // Eigen LU would otherwise run its products on every core.
  const int threads = Eigen::nbThreads();
  Eigen::setNbThreads(1);
  OpticalSetCost out;
  const solver::Network& net = *r.radiative.network;
  const orbits::EnvironmentLoads& e = r.sweep->irradiance;
  out.n = net.size();
  out.rank = r.radiative.pairs.rank();
  out.positions = static_cast<int>(e.direct.cols());
  auto t0 = Clock::now();
  const cases::BandCores cores = cases::bandCores(r.radiative, set);
  out.cores_s = since(t0);
  t0 = Clock::now();
  const Eigen::MatrixXd q_core = cases::absorbedPower(*cores.solar, *cores.ir, r.radiative, e, r.solver.refineTolerance());
  out.solves_s = since(t0);
  t0 = Clock::now();
  const Eigen::MatrixXd q_lu = denseLuAbsorbed(net, set, e);
  out.lu_s = since(t0);
  t0 = Clock::now();
  const Eigen::MatrixXd q_rank_k = cases::absorbedPower(*cores.solar, *cores.ir, r.radiative, e, 0.0);
  out.unrefined_s = since(t0);
  for (int i = 0; i < out.n; ++i) {
    const double scale = q_lu.row(i).cwiseAbs().maxCoeff();
    if (!(scale > 0)) continue;
    out.worst = std::max(out.worst, (q_core.row(i) - q_lu.row(i)).cwiseAbs().maxCoeff() / scale);
    out.unrefined_worst = std::max(out.unrefined_worst, (q_rank_k.row(i) - q_lu.row(i)).cwiseAbs().maxCoeff() / scale);
  }
  t0 = Clock::now();
  out.gr_method = solver::policy::exchangeFactors(net, r.radiative.pairs, set.emissivity, r.solver).method;
  out.gr_s = since(t0);
  for (const auto& [stage, s] : r.timings.entries())
    if (stage == cases::Stage::Eigendecomposition) out.eigen_s = s;
  Eigen::setNbThreads(threads);
  return out;
}

void writeCostTable(std::ostream& md, const OpticalSetCost& c) {
  md << "| " << c.n << " | " << c.rank << " | " << c.positions << " | " << c.cores_s << " | " << c.solves_s << " | **"
     << c.cores_s + c.solves_s << "** | " << c.lu_s << " | **" << c.lu_s / (c.cores_s + c.solves_s) << "×** | "
     << c.worst << " | " << c.cores_s + c.unrefined_s << " | **" << c.lu_s / (c.cores_s + c.unrefined_s) << "×** | "
     << c.unrefined_worst << " | " << c.gr_s << " (" << c.gr_method << ") | " << c.eigen_s << " |\n";
}

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::cerr << "usage: bench_design_cases <design-case.yaml> <out.md> [<larger-case.yaml>]\n";
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
  const OpticalSetCost design = opticalSetCost(r, c.optical_sets.back());
  std::optional<OpticalSetCost> large;
  if (argc == 4) {
    cases::LoadedCase big = cases::loadCase(argv[3]);
    cases::GeometryCase& g = *big.geometry;
    cases::OpticalSet extra = g.optical_sets.front();
    extra.name = "extra";
    extra.absorptivity = (extra.absorptivity.array() + 0.15).min(1.0);
    extra.emissivity = (extra.emissivity.array() - 0.05).max(0.0);
    large = opticalSetCost(cases::runGeometryCase(g, false, quiet), extra);
  }
  double t_thermal = 0.0;
  for (const auto& [stage, s] : r.timings.entries())
    if (stage == cases::Stage::Thermal) t_thermal = s;
  // 3. 64 samples on the one decomposition.
  c.optical_uncertainty = sampling;
  c.optical_uncertainty->samples = 64;
  const cases::GeometryRunResult ru = cases::runGeometryCase(c, false, quiet);
  const double t_samples = ru.optical_uncertainty->sample_seconds;

  std::ofstream md(argv[2]);
  md << std::setprecision(3);
  md << "# Design cases on one eigendecomposition\n\n"
     << "Measured by `make bench` (`build/bench/bench_design_cases " << argv[1] << " … " << (argc == 4 ? argv[3] : "")
     << "`) on " << machine() << ", one process; the optical-set comparison on one core for both sides. "
     << "The design case: " << design.n
     << " nodes, hot (EOL optics) and cold (BOL) cases, steady temperatures, solver tolerance "
     << r.solver.refineTolerance() << ".\n\n"
     << "## One more optical set\n\n"
     << "Radiative part: the set's two k×k band cores, then the band solves of every position "
     << "(direct, albedo and Earth IR, refined with the full G to the solver tolerance), against a "
     << "dense LU of (I − S F) per band and the same solves; the two answers' largest difference "
     << "relative to a node's orbit-maximum absorbed power; the same for the rank-k answer without "
     << "refinement (what a case pinning `rank` without `refine` gets); then what the set costs besides.\n\n"
     << "| nodes | rank | positions | cores, s | band solves, s | on the decomposition, s | dense LU per band, s "
        "| ratio | difference | unrefined rank-k, s | ratio | its difference | GR, s | a new decomposition, s |\n"
     << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  writeCostTable(md, design);
  if (large) writeCostTable(md, *large);
  md << "\nThe temperatures of the design case's two cases (steady per position) took " << t_thermal << " s.\n\n"
     << "## 64 samples of α and ε\n\n"
     << "| | s |\n|---|---|\n"
     << "| one full run of both cases (median of 3) | " << full[1] << " |\n"
     << "| 64 separate full runs (64 × that) | " << 64 * full[1] << " |\n"
     << "| 64 samples on the one decomposition | " << t_samples << " |\n"
     << "| ratio | **" << 64 * full[1] / t_samples << "×** |\n\n"
     << "A sample costs the cores, band solves and GR of each optical set a case uses, and the "
     << "temperatures of every case; view factors, loads and the decomposition are not redone.\n";
  std::cout << "one optical set at " << design.n << " nodes: " << design.cores_s + design.solves_s
            << " s on the decomposition, " << design.lu_s << " s by dense LU; 64 samples " << t_samples
            << " s against " << 64 * full[1] << " s\n";
  return 0;
}
