#include "cases/output/hdf5_layout.hpp"
#include "cases/output/hdf5_matrices.hpp"

#include "cases/pipeline/optical_uncertainty.hpp"

#include <algorithm>

namespace radnet::cases {
namespace {

Eigen::VectorXi integers(const std::vector<int>& v) {
  return Eigen::Map<const Eigen::VectorXi>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// /optics/<set>: every optical set's α, ε and GR; base's GR is the run's (a link, no copy).
void writeOptics(Hdf5Writer& h5, const GeometryCase& c, const DesignCasesResult& cases) {
  for (size_t k = 0; k < c.optical_sets.size(); ++k) {
    const OpticalSet& set = c.optical_sets[k];
    const std::string group = "/optics/" + set.name;
    // The surfaces' own ε, α (the network's are ε/κ, α/κ where a surface is specular).
    h5.writeVector(group + "/emissivity", set.surface_emissivity, "1");
    h5.writeVector(group + "/absorptivity", set.surface_absorptivity, "1");
    if (!set.specular_ir.empty()) {
      h5.writeVector(group + "/specular_reflectance", set.specular_ir.specular, "1");
      h5.writeVector(group + "/transmittance", set.specular_ir.transmittance, "1");
      h5.writeVector(group + "/solar_specular_reflectance", set.specular_solar.specular, "1");
      h5.writeVector(group + "/solar_transmittance", set.specular_solar.transmittance, "1");
    }
    if (k == 0) {
      if (h5.has("/network/radiative_exchange")) h5.link("/network/radiative_exchange", group + "/radiative_exchange");
      h5.link("/network/gr_space", group + "/gr_space");
      if (h5.has("/network/radiative_exchange_factors"))
        h5.link("/network/radiative_exchange_factors", group + "/radiative_exchange_factors");
      continue;
    }
    const solver::ExchangeFactors& ex = cases.optics_exchange[k - 1];
    writeExchange(h5, group + "/", ex, c.output.denseExchange(ex.size(), !ex.factored()));
  }
}

void writeCaseTemperatures(Hdf5Writer& h5, const DesignCasesResult& cases) {
  if (cases.temperature_min.size() == 0) return;
  h5.writeMatrix("/solution/case_temperature_min", cases.temperature_min, "K");
  h5.writeMatrix("/solution/case_temperature_mean", cases.temperature_mean, "K");
  h5.writeMatrix("/solution/case_temperature_max", cases.temperature_max, "K");
  h5.attribute("/solution/case_temperature_mean", "meaning",
               std::string("time-weighted mean over each design case's positions (periodic trapezoid rule per orbit "
                           "case, each orbit case weighted by the time its sweep spans)"));
  h5.writeVector("/cases/time_weight", cases.time_weight, "1");
  h5.attribute("/cases/time_weight", "meaning",
               std::string("each position's weight in its design case's time mean (sums to 1 per design case): "
                           "the weights of /solution/case_temperature_mean"));
  h5.writeVector("/solution/envelope/temperature_min", cases.envelope_min, "K");
  h5.writeVector("/solution/envelope/temperature_max", cases.envelope_max, "K");
  h5.writeIntegers("/solution/envelope/temperature_min_case", cases.envelope_min_case, "1");
  h5.writeIntegers("/solution/envelope/temperature_max_case", cases.envelope_max_case, "1");
  h5.attribute("/solution/envelope", "case", std::string("the _case datasets index /cases/name"));
}

}  // namespace

void writeDesignCases(Hdf5Writer& h5, const GeometryCase& c, const GeometryRunResult& r) {
  const DesignCasesResult& cases = r.cases;
  h5.writeStrings("/cases/name", cases.names);
  h5.writeStrings("/cases/optics", cases.optics);
  Eigen::VectorXd scale(cases.caseCount());
  for (int k = 0; k < cases.caseCount(); ++k) scale[k] = c.design_cases[static_cast<size_t>(k)].dissipation_scale;
  h5.writeVector("/cases/dissipation_scale", scale, "1");
  h5.writeIntegers("/cases/orbit_case_start", integers(cases.orbit_case_start), "1");
  h5.writeIntegers("/cases/position_start", integers(cases.position_start), "1");
  h5.attribute("/cases", "meaning",
               std::string("design case k has the orbit cases (/orbit/case_label) orbit_case_start[k] … "
                           "orbit_case_start[k+1]−1 and the positions position_start[k] … position_start[k+1]−1"));
  if (r.sweep) {
    std::vector<int> design(r.sweep->positions.size());
    for (int k = 0; k < cases.caseCount(); ++k)
      for (int p = cases.position_start[static_cast<size_t>(k)]; p < cases.position_start[static_cast<size_t>(k) + 1];
           ++p)
        design[static_cast<size_t>(p)] = k;
    h5.writeIntegers("/orbit/design_case", integers(design), "1");
  }
  writeOptics(h5, c, cases);
  writeCaseTemperatures(h5, cases);
  h5.attribute("/report", "eigendecompositions", static_cast<long long>(cases.eigendecompositions));
  h5.attribute("/report", "band_cores", static_cast<long long>(cases.band_cores));
  h5.attribute("/report", "design_cases", static_cast<long long>(cases.caseCount()));
  // Per case and stage: in /report/cases/<case> as time_<stage>_s, and flat in /report as
  // case_<case>_time_<stage>_s for readers that list /report's attributes only.
  for (int k = 0; k < cases.caseCount(); ++k) {
    const std::string& name = cases.names[static_cast<size_t>(k)];
    for (const auto& [stage, seconds] : cases.timings[static_cast<size_t>(k)].entries()) {
      const std::string attr = "time_" + std::string(stageName(stage)) + "_s";
      h5.attribute("/report/cases/" + name, attr, seconds);
      h5.attribute("/report", "case_" + name + "_" + attr, seconds);
    }
  }
}

void writeOpticalUncertainty(Hdf5Writer& h5, const GeometryCase& c, const OpticalUncertaintyResult& u) {
  const OpticalUncertainty& spec = *c.optical_uncertainty;
  const std::string pct = "/uncertainty/temperature_percentiles";
  h5.writeStack(pct, {u.percentiles[0], u.percentiles[1], u.percentiles[2]}, "K");
  h5.attribute(pct, "percentiles", std::string("5, 50, 95"));
  h5.attribute(pct, "sampled",
               std::string("[0]: the 5th percentile of each sample's orbit minimum; [1]: the median of each sample's "
                           "time-weighted orbit mean; [2]: the 95th percentile of each sample's orbit maximum; per "
                           "design case (/cases/name) and node"));
  h5.attribute(pct, "samples", static_cast<long long>(u.samples));
  h5.attribute(pct, "absorptivity_sigma", spec.absorptivity_sigma);
  h5.attribute(pct, "emissivity_sigma", spec.emissivity_sigma);
  h5.attribute(pct, "seed", static_cast<long long>(spec.seed));
  h5.attribute(pct, "clipped_absorptivity", u.clipped_absorptivity);
  h5.attribute(pct, "clipped_emissivity", u.clipped_emissivity);
  if (c.thermal->periodic)
    h5.attribute(pct, "sample_periodic_tolerance", kSamplePeriodicFactor * c.thermal->periodic->tolerance_k);
  h5.attribute(pct, "method",
               std::string("each material's α and ε drawn independently, normal, clipped to [0, 1], the same draw in "
                           "every optical set; every sample on the one eigendecomposition"));
  h5.writeStack("/uncertainty/temperature_samples_min", u.sample_min, "K");
  h5.writeStack("/uncertainty/temperature_samples_mean", u.sample_mean, "K");
  h5.writeStack("/uncertainty/temperature_samples_max", u.sample_max, "K");
  h5.writeStrings("/uncertainty/materials", u.materials);
  const std::string meaning = "K per unit change of each material's property (rows: /uncertainty/materials) on the "
                              "orbit-mean temperature, by central differences of ±" + std::to_string(u.step) +
                              " (one-sided at 0 or 1) on the same decomposition";
  h5.writeMatrix("/uncertainty/sensitivity_absorptivity", u.sensitivity_absorptivity, "K");
  h5.writeMatrix("/uncertainty/sensitivity_emissivity", u.sensitivity_emissivity, "K");
  h5.attribute("/uncertainty/sensitivity_absorptivity", "meaning", meaning + "; the mean over the design cases");
  h5.attribute("/uncertainty/sensitivity_emissivity", "meaning", meaning + "; the mean over the design cases");
  h5.writeStack("/uncertainty/case_sensitivity_absorptivity", u.case_sensitivity_absorptivity, "K");
  h5.writeStack("/uncertainty/case_sensitivity_emissivity", u.case_sensitivity_emissivity, "K");
  h5.attribute("/report", "optical_uncertainty_seconds", u.seconds);
}

void writeArticulation(Hdf5Writer& h5, const GeometryCase& c, const GeometryRunResult& r) {
  if (!r.articulation) return;
  const ArticulationResult& a = *r.articulation;
  h5.writeStrings("/articulation/name", a.names);
  const Eigen::Index m = static_cast<Eigen::Index>(a.names.size());
  Eigen::MatrixXd angle;
  if (r.sweep && r.sweep->articulation_angle.size()) {
    angle = r.sweep->articulation_angle;
  } else {  // fixed angles only: the same at every position
    const Eigen::Index P = r.sweep ? static_cast<Eigen::Index>(r.sweep->positions.size()) : 1;
    angle.resize(P, m);
    for (Eigen::Index d = 0; d < m; ++d) angle.col(d).setConstant(c.articulation.fixed_drives[static_cast<size_t>(d)].second);
  }
  h5.writeMatrix("/articulation/angle", angle, "deg");
  h5.attribute("/articulation", "meaning",
               std::string("angle (P, drives): each drive's angle at each position, right-handed about its axis, "
                           "0 the geometry as written; the configurations the positions were solved in (the "
                           "turning drives' angles binned to their step) with their GR and vertices; /network/* is "
                           "configuration 0, the geometry with the turning parts as written"));
  if (a.vertices.empty()) return;
  h5.writeIntegers("/articulation/configuration", integers(r.sweep->configuration), "1");
  h5.writeMatrix("/articulation/configuration_angle", a.configuration_angle, "deg");
  h5.writeIntegers("/articulation/update_rank", integers(a.update_rank), "1");
  // Each configuration's GR as a group of its own (configuration 0's are /network's, linked):
  // what a reader or `radnet export` of one position takes as it takes /network's.
  const double n = double(a.exchange.front().size());
  const double entries = double(a.exchange.size()) * n * n;
  constexpr double kMaxExchangeEntries = 2e7;  // 160 MB of dense GR: beyond, the factored forms only
  const bool factored = std::all_of(a.exchange.begin(), a.exchange.end(), [](const auto& ex) { return ex.factored(); });
  const bool dense = entries <= kMaxExchangeEntries && c.output.denseExchange(static_cast<long>(n), !factored);
  if (entries <= kMaxExchangeEntries || factored) {
    for (size_t k = 0; k < a.exchange.size(); ++k) {
      const std::string group = "/articulation/configuration_" + std::to_string(k) + "/";
      if (k == 0 && r.radiative.exchange) {
        if (h5.has("/network/radiative_exchange")) h5.link("/network/radiative_exchange", group + "radiative_exchange");
        h5.link("/network/gr_space", group + "gr_space");
        if (h5.has("/network/radiative_exchange_factors"))
          h5.link("/network/radiative_exchange_factors", group + "radiative_exchange_factors");
        continue;
      }
      writeExchange(h5, group, a.exchange[k], dense);
    }
  } else {
    h5.attribute("/articulation", "radiative_exchange",
                 std::string("not written: ") + std::to_string(a.exchange.size()) + " configurations × n² is above " +
                     std::to_string(static_cast<long long>(kMaxExchangeEntries)) + " entries");
  }
  h5.writeStack("/articulation/vertices", a.vertices, "m");
  h5.attribute("/report", "articulation_configurations", static_cast<long long>(a.vertices.size()));
  h5.attribute("/report", "articulation_recast_rows", static_cast<long long>(a.recast_rows));
  h5.attribute("/report", "articulation_rays", static_cast<long long>(a.rays));
  h5.attribute("/report", "articulation_integrated_rows", static_cast<long long>(a.integrated_rows));
  h5.attribute("/report", "articulation_pairs", static_cast<long long>(a.pairs));
  h5.attribute("/report", "articulation_largest_update_rank",
               static_cast<long long>(*std::max_element(a.update_rank.begin(), a.update_rank.end())));
}

}  // namespace radnet::cases
