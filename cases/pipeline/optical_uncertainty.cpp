#include "cases/pipeline/optical_uncertainty.hpp"

#include "cases/config/errors.hpp"
#include "cases/pipeline/orbit_sweep.hpp"
#include "cases/pipeline/progress.hpp"
#include "cases/pipeline/radiative_network.hpp"
#include "cases/pipeline/thermal_run.hpp"

#include <algorithm>
#include <chrono>
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

// d(orbit-mean T)/d(property) of each material by central differences (one-sided at 0 or 1).
void sensitivities(const DesignContext& ctx, const std::vector<CaseRun>& runs, bool absorptivity,
                   OpticalUncertaintyResult& out, int& band_cores, std::ostream& progress) {
  const GeometryCase& c = ctx.c;
  const Eigen::Index M = static_cast<Eigen::Index>(out.materials.size());
  const int cases = static_cast<int>(c.design_cases.size());
  std::vector<Eigen::MatrixXd>& per_case = absorptivity ? out.case_sensitivity_absorptivity : out.case_sensitivity_emissivity;
  per_case.assign(static_cast<size_t>(cases), Eigen::MatrixXd());
  for (Eigen::Index m = 0; m < M; ++m) {
    const auto [up, down] = steps(c, out.materials[static_cast<size_t>(m)], absorptivity);
    Eigen::VectorXd shift_up = Eigen::VectorXd::Zero(M), shift_down = Eigen::VectorXd::Zero(M);
    shift_up[m] = up;
    shift_down[m] = -down;
    const Eigen::VectorXd none = Eigen::VectorXd::Zero(M);
    const CaseTemperatures hi = caseTemperaturesUnder(
        ctx, runs, absorptivity ? shiftedSets(c, out.materials, shift_up, none) : shiftedSets(c, out.materials, none, shift_up),
        band_cores);
    const CaseTemperatures lo = caseTemperaturesUnder(
        ctx, runs,
        absorptivity ? shiftedSets(c, out.materials, shift_down, none) : shiftedSets(c, out.materials, none, shift_down),
        band_cores);
    const double span = up + down;
    if (!(span > 1e-9))
      progress << "radnet: warning: the " << (absorptivity ? "absorptivity" : "emissivity") << " of '"
               << out.materials[static_cast<size_t>(m)] << "' is 0 in one optical set and 1 in another: its "
               << "sensitivity is left at 0\n";
    for (int k = 0; k < cases; ++k) {
      Eigen::MatrixXd& s = per_case[static_cast<size_t>(k)];
      if (s.size() == 0) s.setZero(M, hi.mean.cols());
      if (span > 1e-9) s.row(m) = (hi.mean.row(k) - lo.mean.row(k)) / span;
    }
  }
  Eigen::MatrixXd& mean = absorptivity ? out.sensitivity_absorptivity : out.sensitivity_emissivity;
  mean = per_case.front();
  for (size_t k = 1; k < per_case.size(); ++k) mean += per_case[k];
  mean /= static_cast<double>(cases);
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

}  // namespace

std::vector<OpticalSet> shiftedSets(const GeometryCase& c, const std::vector<std::string>& materials,
                                    const Eigen::VectorXd& da, const Eigen::VectorXd& de) {
  std::vector<OpticalSet> sets = c.optical_sets;
  for (size_t i = 0; i < c.node_material.size(); ++i) {
    const auto m = std::lower_bound(materials.begin(), materials.end(), c.node_material[i]) - materials.begin();
    const auto k = static_cast<Eigen::Index>(i);
    for (OpticalSet& set : sets) {
      set.absorptivity[k] = std::clamp(set.absorptivity[k] + da[m], 0.0, 1.0);
      set.emissivity[k] = std::clamp(set.emissivity[k] + de[m], 0.0, 1.0);
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
      forcing = thermalForcing(*run.sweep, absorbedPower(*cores[o].solar, *cores[o].ir, *ctx.radiative.network,
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
  out.materials = c.surfaceMaterials();
  out.samples = u.samples;
  out.step = kSensitivityStep;
  const Eigen::Index M = static_cast<Eigen::Index>(out.materials.size());
  NormalDraws normal(u.seed);
  const auto bar = show_progress ? progressBar(progress, "optical samples", "samples") : std::function<void(int, int)>();
  for (int s = 0; s < u.samples; ++s) {
    Eigen::VectorXd da(M), de(M);
    for (Eigen::Index m = 0; m < M; ++m) {
      da[m] = u.absorptivity_sigma * normal.next();
      de[m] = u.emissivity_sigma * normal.next();
    }
    try {
      const CaseTemperatures t = caseTemperaturesUnder(ctx, runs, shiftedSets(c, out.materials, da, de), band_cores);
      out.sample_min.push_back(t.min);
      out.sample_mean.push_back(t.mean);
      out.sample_max.push_back(t.max);
    } catch (const NumericalError& e) {
      throw NumericalError("optical uncertainty sample " + std::to_string(s + 1) + ": " + e.what());
    }
    if (bar) bar(s + 1, u.samples);
  }
  out.sample_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.percentiles = {percentileOf(out.sample_min, 5), percentileOf(out.sample_mean, 50),
                     percentileOf(out.sample_max, 95)};
  sensitivities(ctx, runs, true, out, band_cores, progress);
  sensitivities(ctx, runs, false, out, band_cores, progress);
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress << "radnet: optical uncertainty: " << u.samples << " samples (σ_α " << u.absorptivity_sigma << ", σ_ε "
           << u.emissivity_sigma << ") and " << 4 * M << " finite-difference variants of " << M
           << " material(s) on the one eigendecomposition, " << out.seconds << " s\n";
  return out;
}

}  // namespace radnet::cases
