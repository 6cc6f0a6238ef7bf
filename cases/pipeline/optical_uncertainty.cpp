#include "cases/pipeline/optical_uncertainty.hpp"

#include "cases/cluster/cluster.hpp"
#include "cases/config/errors.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/orbit_sweep.hpp"
#include "cases/pipeline/progress.hpp"
#include "cases/pipeline/radiative_network.hpp"
#include "cases/pipeline/thermal_run.hpp"
#include "solver/parallel.hpp"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <cmath>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>

namespace radnet::cases {
namespace {

// Standard normal draws by Box–Muller from a 64-bit Mersenne twister: the same numbers on
// every platform for a seed (std::normal_distribution's algorithm is the library's choice).
class NormalDraws {
 public:
  explicit NormalDraws(std::uint64_t seed) : rng_(seed) {}
  double next() {
    if (spare_) {
      const double z = *spare_;
      spare_.reset();
      return z;
    }
    constexpr double kTwoPi = 6.283185307179586;
    const double u1 = (static_cast<double>(rng_() >> 11) + 0.5) * 0x1.0p-53;  // (0, 1)
    const double u2 = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
    const double r = std::sqrt(-2.0 * std::log(u1));
    spare_ = r * std::sin(kTwoPi * u2);
    return r * std::cos(kTwoPi * u2);
  }

 private:
  std::mt19937_64 rng_;
  std::optional<double> spare_;
};

// The p-th percentile (0…100) of `v` by linear interpolation between order statistics
// (numpy's default), so a user's np.percentile of the samples gives the same number.
double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const double pos = p / 100.0 * static_cast<double>(v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(pos));
  const size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

Eigen::MatrixXd percentileOf(const std::vector<Eigen::MatrixXd>& samples, double p) {
  Eigen::MatrixXd out(samples.front().rows(), samples.front().cols());
  std::vector<double> v(samples.size());
  for (Eigen::Index i = 0; i < out.size(); ++i) {
    for (size_t s = 0; s < samples.size(); ++s) v[s] = samples[s](i);
    out(i) = percentile(v, p);
  }
  return out;
}

// The largest steps up and down each material's property may take in every optical set
// without leaving [0, 1].
std::pair<double, double> steps(const GeometryCase& c, const std::string& material, bool absorptivity) {
  double up = kSensitivityStep, down = kSensitivityStep;
  for (const OpticalSet& set : c.optical_sets)
    for (size_t i = 0; i < c.node_material.size(); ++i) {
      if (c.node_material[i] != material) continue;
      const double v = (absorptivity ? set.absorptivity : set.emissivity)[static_cast<Eigen::Index>(i)];
      up = std::min(up, 1.0 - v);
      down = std::min(down, v);
    }
  return {up, down};
}

// Under MPI each rank solved the items (samples, variants) it owns: every item's matrices,
// scalars and band-core counts on every rank. An item's matrix is empty where it was not
// solved, and zero-filled to the common shape before the join.
void joinItems(const std::vector<Eigen::MatrixXd*>& items, std::vector<double>& scalars, std::vector<int>& cores) {
  if (!cluster::distributed()) return;
  double shape[2] = {0, 0};
  for (const Eigen::MatrixXd* m : items) {
    shape[0] = std::max(shape[0], static_cast<double>(m->rows()));
    shape[1] = std::max(shape[1], static_cast<double>(m->cols()));
  }
  cluster::max(shape, 2);
  for (Eigen::MatrixXd* m : items)
    if (m->size() == 0) m->setZero(static_cast<Eigen::Index>(shape[0]), static_cast<Eigen::Index>(shape[1]));
  joinOverRanks(items);
  cluster::join(scalars.data(), scalars.size());
  std::vector<std::int64_t> counts(cores.begin(), cores.end());
  cluster::sum(counts.data(), counts.size());
  std::copy(counts.begin(), counts.end(), cores.begin());
}

// d(orbit-mean T)/d(property) of each material by central differences (one-sided at 0 or
// 1): 2 variants per material and property, evaluated in parallel.
void sensitivities(const DesignContext& ctx, const std::vector<CaseRun>& runs, OpticalUncertaintyResult& out,
                   int& band_cores, std::ostream& progress) {
  const GeometryCase& c = ctx.c;
  const Eigen::Index M = static_cast<Eigen::Index>(out.materials.size());
  const int cases = static_cast<int>(c.design_cases.size());
  // Variant v: property v / (2M) (0: α, 1: ε), material (v / 2) % M, up (even v) or down.
  const long long variants = 4 * M;
  std::vector<CaseTemperatures> result(static_cast<size_t>(variants));
  std::vector<double> step(static_cast<size_t>(variants));
  std::vector<int> cores(static_cast<size_t>(variants), 0);
  std::vector<char> used(static_cast<size_t>(M), 0);  // a material on no surface: a zero row, nothing solved
  for (Eigen::Index m = 0; m < M; ++m)
    used[static_cast<size_t>(m)] =
        std::find(c.node_material.begin(), c.node_material.end(), out.materials[static_cast<size_t>(m)]) !=
        c.node_material.end();
  solver::parallelFor(variants, [&](long long v) {
    const bool absorptivity = v < 2 * M, up = v % 2 == 0;
    const Eigen::Index m = (v / 2) % M;
    if (!used[static_cast<size_t>(m)] || !cluster::owns(v)) return;
    const auto [max_up, max_down] = steps(c, out.materials[static_cast<size_t>(m)], absorptivity);
    Eigen::VectorXd shift = Eigen::VectorXd::Zero(M);
    const Eigen::VectorXd none = Eigen::VectorXd::Zero(M);
    shift[m] = up ? max_up : -max_down;
    step[static_cast<size_t>(v)] = shift[m];
    result[static_cast<size_t>(v)] = caseTemperaturesUnder(
        ctx, runs, absorptivity ? shiftedSets(c, out.materials, shift, none) : shiftedSets(c, out.materials, none, shift),
        cores[static_cast<size_t>(v)]);
  });
  std::vector<Eigen::MatrixXd*> means;
  for (CaseTemperatures& t : result) means.push_back(&t.mean);
  joinItems(means, step, cores);
  for (int n : cores) band_cores += n;
  for (int property = 0; property < 2; ++property) {
    std::vector<Eigen::MatrixXd>& per_case =
        property == 0 ? out.case_sensitivity_absorptivity : out.case_sensitivity_emissivity;
    Eigen::Index nodes = 0;
    for (const CaseTemperatures& t : result) nodes = std::max(nodes, t.mean.cols());
    per_case.assign(static_cast<size_t>(cases), Eigen::MatrixXd::Zero(M, nodes));
    for (Eigen::Index m = 0; m < M; ++m) {
      if (!used[static_cast<size_t>(m)]) continue;
      const auto hi = static_cast<size_t>(2 * (property * M + m)), lo = hi + 1;
      const double span = step[hi] - step[lo];
      if (!(span > 1e-9)) {
        progress << "radnet: warning: the " << (property == 0 ? "absorptivity" : "emissivity") << " of '"
                 << out.materials[static_cast<size_t>(m)] << "' is 0 in one optical set and 1 in another: its "
                 << "sensitivity is left at 0\n";
        continue;
      }
      for (int k = 0; k < cases; ++k)
        per_case[static_cast<size_t>(k)].row(m) = (result[hi].mean.row(k) - result[lo].mean.row(k)) / span;
    }
    Eigen::MatrixXd& mean = property == 0 ? out.sensitivity_absorptivity : out.sensitivity_emissivity;
    mean = per_case.front();
    for (size_t k = 1; k < per_case.size(); ++k) mean += per_case[k];
    mean /= static_cast<double>(cases);
  }
}

// A periodic transient's answer does not depend on where it starts: a variant starts from
// the case's own periodic state and repeats within a few orbits, not the dozens a cold start
// takes. It settles to kSamplePeriodicFactor × the case's tolerance: a thermostat's limit
// cycle need not repeat with the orbit to 0.01 K in every variant, and the spread the
// samples measure is kelvins. Any other transient keeps the initial temperatures given.
ThermalSettings warmStart(const CaseRun& run) {
  ThermalSettings ts = *run.settings;
  if (ts.periodic && run.thermal) {
    ts.initial_temperature = run.thermal->temperature().col(0);
    ts.periodic->tolerance_k *= kSamplePeriodicFactor;
  }
  return ts;
}

// The share of sampled node values that [0, 1] clipped, per property: a large σ against a
// value near 0 or 1 samples a distribution that is no longer normal, and the user is told.
void clippedShares(const GeometryCase& c, OpticalUncertaintyResult& out, const std::vector<Eigen::VectorXd>& da,
                   const std::vector<Eigen::VectorXd>& de, std::ostream& progress) {
  long long total = 0, clipped_a = 0, clipped_e = 0;
  for (size_t s = 0; s < da.size(); ++s)
    for (size_t i = 0; i < c.node_material.size(); ++i) {
      const auto m = std::lower_bound(out.materials.begin(), out.materials.end(), c.node_material[i]) -
                     out.materials.begin();
      for (const OpticalSet& set : c.optical_sets) {
        const double a = set.absorptivity[static_cast<Eigen::Index>(i)] + da[s][m];
        const double e = set.emissivity[static_cast<Eigen::Index>(i)] + de[s][m];
        clipped_a += a < 0.0 || a > 1.0;
        clipped_e += e < 0.0 || e > 1.0;
        ++total;
      }
    }
  out.clipped_absorptivity = total ? double(clipped_a) / double(total) : 0.0;
  out.clipped_emissivity = total ? double(clipped_e) / double(total) : 0.0;
  for (const auto& [share, name] : {std::pair{out.clipped_absorptivity, "absorptivity"},
                                    std::pair{out.clipped_emissivity, "emissivity"}})
    if (share > kClippedWarning)
      progress << "radnet: warning: uncertainty: " << 100.0 * share << " % of the sampled " << name
               << " values fell outside [0, 1] and were clipped: its σ is large against a value near 0 or 1, and "
               << "the percentiles describe the clipped distribution, not a normal one\n";
}

}  // namespace

std::vector<OpticalSet> shiftedSets(const GeometryCase& c, const std::vector<std::string>& materials,
                                    const Eigen::VectorXd& da, const Eigen::VectorXd& de) {
  std::vector<OpticalSet> sets = c.optical_sets;
  for (size_t i = 0; i < c.node_material.size(); ++i) {
    const auto m = std::lower_bound(materials.begin(), materials.end(), c.node_material[i]) - materials.begin();
    const auto k = static_cast<Eigen::Index>(i);
    // With specular surfaces the sets hold ε/κ and α/κ: a shift of ε is one of δε/κ there.
    const double ka = c.hasSpecular() ? c.specular_solar.kappa()[k] : 1.0;
    const double ke = c.hasSpecular() ? c.specular_ir.kappa()[k] : 1.0;
    for (OpticalSet& set : sets) {
      set.absorptivity[k] = ka > 0 ? std::clamp(set.absorptivity[k] + da[m] / ka, 0.0, 1.0) : 0.0;
      set.emissivity[k] = ke > 0 ? std::clamp(set.emissivity[k] + de[m] / ke, 0.0, 1.0) : 0.0;
      set.surface_absorptivity[k] = set.absorptivity[k] * (ka > 0 ? ka : 0.0);  // the surfaces' own, kept in step
      set.surface_emissivity[k] = set.emissivity[k] * (ke > 0 ? ke : 0.0);
    }
  }
  return sets;
}

CaseTemperatures caseTemperaturesUnder(const DesignContext& ctx, const std::vector<CaseRun>& runs,
                                       const std::vector<OpticalSet>& sets, int& band_cores) {
  const GeometryCase& c = ctx.c;
  const int cases = static_cast<int>(c.design_cases.size());
  std::vector<BandCores> cores(sets.size());
  std::vector<std::optional<solver::ExchangeFactors>> exchange(sets.size());
  StageTimings untimed;  // the caller times the whole sampling
  std::ostringstream quiet;
  CaseTemperatures t;
  for (int k = 0; k < cases; ++k) {
    const auto o = static_cast<size_t>(c.design_cases[static_cast<size_t>(k)].optics);
    const CaseRun& run = runs[static_cast<size_t>(k)];
    if (!exchange[o]) exchange[o] = exchangeFactors(ctx.radiative, sets[o].emissivity, ctx.solver, untimed);
    std::optional<SweepResult> forcing;
    if (run.sweep) {
      if (!cores[o].solar) {
        cores[o] = bandCores(ctx.radiative, sets[o]);
        band_cores += 2;
      }
      forcing = thermalForcing(*run.sweep, absorbedPower(*cores[o].solar, *cores[o].ir, ctx.radiative,
                                                         run.sweep->irradiance, ctx.solver.refineTolerance()));
    }
    const ThermalSolution th =
        runThermal(warmStart(run), *exchange[o], forcing ? &*forcing : nullptr, untimed, quiet, nullptr);
    setCaseRow(t, k, cases, th, forcing ? &*forcing : nullptr);
  }
  return t;
}

OpticalUncertaintyResult sampleOpticalUncertainty(const DesignContext& ctx, const std::vector<CaseRun>& runs,
                                                  int& band_cores, bool show_progress, std::ostream& progress) {
  const GeometryCase& c = ctx.c;
  const OpticalUncertainty& u = *c.optical_uncertainty;
  const auto start = std::chrono::steady_clock::now();
  OpticalUncertaintyResult out;
  out.materials = c.opticalMaterials();
  out.samples = u.samples;
  out.step = kSensitivityStep;
  const Eigen::Index M = static_cast<Eigen::Index>(out.materials.size());
  // Draws first, in sample order: the same numbers whatever the thread count.
  NormalDraws normal(u.seed);
  std::vector<Eigen::VectorXd> da(static_cast<size_t>(u.samples), Eigen::VectorXd(M)), de = da;
  for (int s = 0; s < u.samples; ++s)
    for (Eigen::Index m = 0; m < M; ++m) {
      da[static_cast<size_t>(s)][m] = u.absorptivity_sigma * normal.next();
      de[static_cast<size_t>(s)][m] = u.emissivity_sigma * normal.next();
    }
  clippedShares(c, out, da, de, progress);
  const auto bar = show_progress ? progressBar(progress, "optical samples", "samples") : std::function<void(int, int)>();
  std::mutex bar_mutex;
  int done = 0;
  std::vector<int> cores(static_cast<size_t>(u.samples), 0);
  const std::vector<char> owned = cluster::ownedMask(u.samples);
  const long long mine = std::count(owned.begin(), owned.end(), 1);
  for (auto* v : {&out.sample_min, &out.sample_mean, &out.sample_max}) v->resize(static_cast<size_t>(u.samples));
  solver::parallelFor(u.samples, [&](long long s) {
    const auto k = static_cast<size_t>(s);
    if (!cluster::owns(s)) return;  // another MPI rank's
    try {
      CaseTemperatures t = caseTemperaturesUnder(ctx, runs, shiftedSets(c, out.materials, da[k], de[k]), cores[k]);
      out.sample_min[k] = std::move(t.min);
      out.sample_mean[k] = std::move(t.mean);
      out.sample_max[k] = std::move(t.max);
    } catch (const NumericalError& e) {
      throw NumericalError("optical uncertainty sample " + std::to_string(s + 1) + ": " + e.what());
    }
    const std::lock_guard<std::mutex> lock(bar_mutex);
    ++done;
    if (bar) bar(done, static_cast<int>(mine));
  });
  std::vector<Eigen::MatrixXd*> samples;
  for (auto* v : {&out.sample_min, &out.sample_mean, &out.sample_max})
    for (Eigen::MatrixXd& m : *v) samples.push_back(&m);
  std::vector<double> no_scalars;
  joinItems(samples, no_scalars, cores);
  for (int n : cores) band_cores += n;
  out.sample_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.percentiles = {percentileOf(out.sample_min, 5), percentileOf(out.sample_mean, 50),
                     percentileOf(out.sample_max, 95)};
  sensitivities(ctx, runs, out, band_cores, progress);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress << "radnet: optical uncertainty: " << u.samples << " samples (σ_α " << u.absorptivity_sigma << ", σ_ε "
           << u.emissivity_sigma << ") and the α and ε sensitivities of " << M
           << " material(s), on the one eigendecomposition, " << out.seconds << " s\n";
  return out;
}

}  // namespace radnet::cases
