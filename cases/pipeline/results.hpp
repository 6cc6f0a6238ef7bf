#pragma once
// What a run computes, as the output writers and `radnet check` read it. Derived
// quantities (total absorbed power, the triangle → node map) are computed once here by
// the pipeline, never re-summed by a writer.
#include "cases/pipeline/stages.hpp"
#include "geometry/rays/specular.hpp"
#include "geometry/reciprocity.hpp"
#include "orbits/loads.hpp"
#include "orbits/sweep.hpp"
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/exchange.hpp"
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/network.hpp"
#include "solver/radiative/settings.hpp"
#include "solver/thermal/temperatures.hpp"
#include "solver/radiative/uncertainty.hpp"

#include <Eigen/Dense>

#include <array>
#include <cstdint>
#include <memory>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

/// The radiative network of a run, its one eigendecomposition and its exchange factors;
/// the same for both case forms.
struct RadiativeNetwork {
  /// The IR band's network (both bands' when no surface is specular or transmissive). With
  /// specular surfaces its areas are Ã = A κ and its F̃ = E^s κ (docs/solver.md).
  std::unique_ptr<solver::Network> network;
  /// The solar band's own network when its specular optics differ from the IR band's (its
  /// band solves are brought to the tolerance with the full G̃ of this network, the one
  /// eigendecomposition's core their preconditioner); null: `network` serves both bands.
  std::unique_ptr<solver::Network> solar_network;
  /// The nodes' own areas, m² (the network's are A κ where a surface is specular); empty:
  /// the network's areas are the nodes' own.
  Eigen::VectorXd surface_area;
  /// κ = 1 − ρs − τ per node in each band (the network's radiosity M̃ is J / κ); empty: 1.
  Eigen::VectorXd kappa_ir, kappa_solar;
  /// ρs and τ per node in the solar band (empty: none): the loads follow sunlight through them.
  geometry::SpecularBand solar_specular, ir_specular;
  const solver::Network& solarNetwork() const { return solar_network ? *solar_network : *network; }
  const Eigen::VectorXd& surfaceArea() const { return surface_area.size() ? surface_area : network->area(); }
  solver::EigenPairs pairs;
  std::optional<solver::ExchangeFactors> exchange;  ///< GR, when the nodes' emissivities are known
};

/// The absorbed-power uncertainty against the budget: for each node the largest σ over the
/// positions relative to its orbit-maximum absorbed power, then the largest over nodes
/// (nodes that never absorb anything are left out).
struct UncertaintySummary {
  double total = 0.0, view_factors = 0.0, loads = 0.0, truncation = 0.0;  ///< –
  int worst_node = -1;         ///< where `total` is reached
  int nodes_over_budget = 0;   ///< nodes whose relative σ exceeds the accuracy asked for
  double accuracy = 0.0;       ///< solver.accuracy, –
};

/// An orbit sweep: the positions of every orbit case, their loads and band solves.
struct SweepResult {
  std::vector<orbits::SweepPosition> positions;  ///< of every orbit case, one after another
  std::vector<int> case_start;                   ///< first position of each case, then P
  std::vector<std::string> case_labels;
  std::vector<double> case_period_s;    ///< each case's nodal orbit period, s (Orbit::nodalPeriod)
  std::vector<double> case_sweep_s;     ///< time each case's sweep spans (nodal period × orbits), s
  orbits::EnvironmentLoads irradiance;  ///< external irradiances, W/m² (n×P)
  std::string central_body = "earth";  ///< what the orbits go round (orbit.body)
  std::string planet_ir_model;         ///< PlanetIr::describe() of the loads' planet IR
  Eigen::MatrixXd absorbed_solar, absorbed_albedo, absorbed_earth_ir;  ///< after interreflection, W (n×P)
  Eigen::MatrixXd absorbed_total;                                      ///< solar + albedo + Earth IR, W (n×P)
  Eigen::MatrixXd exitance_solar;                  ///< solar-band exitance (direct + albedo), W/m² (n×P)
  double solar_residual = 0.0, ir_residual = 0.0;  ///< band-solve residuals with the full G
  int solar_refine_iterations = 0, ir_refine_iterations = 0;
  /// How each band reached its tolerance (BandSolution::method; several design cases'
  /// different methods joined by ", ").
  std::string solar_band_method, ir_band_method;
  double energy_balance_error = 0.0;  ///< max over positions of |in − absorbed − lost| / in, solar band
  /// Standard uncertainty of absorbed_total (n×P), W, and its parts: the view factors'
  /// errors (both bands, taken as fully correlated), the loads' sampling, the truncation.
  Eigen::MatrixXd absorbed_stderr, absorbed_stderr_view_factors, absorbed_stderr_loads, absorbed_stderr_truncation;
  UncertaintySummary uncertainty;
  /// With turning parts: every drive's angle at each position (P × drives), deg, and the
  /// configuration each position was solved in (P); empty otherwise.
  Eigen::MatrixXd articulation_angle;
  std::vector<int> configuration;
  int caseCount() const { return static_cast<int>(case_start.size()) - 1; }
};

/// Where each node's heat comes from and goes to, per position, and how well it balances.
struct HeatBalance {
  solver::HeatFlows flows;              ///< (n×P) W, positive into the node; environment loads are in the sweep
  double max_imbalance_w = 0.0;         ///< largest |Σ of all terms| beyond round-off over nodes and positions, W
  double max_relative_imbalance = 0.0;  ///< the same, each relative to the largest |term| of its node and position (at least 1e-6 of the position's largest)
};

/// Temperatures and heat flows of the thermal model: its nodes are the radiative nodes
/// followed by the lumped ones.
struct ThermalSolution {
  std::vector<std::string> node_names;  ///< the rows of every (n×P) matrix below
  int radiative_nodes = 0;              ///< the first nodes, which have geometry or a network row
  solver::ThermalResult solve;          ///< temperature (n×P), K, and how the solve went
  std::string mode;                     ///< "steady", "transient", "periodic transient" or "transient without orbit"
  std::vector<double> times_s;          ///< the P output times (s; for a transient without an orbit, from its start)
  std::vector<std::string> heater_names;
  std::vector<double> heater_rated_w;  ///< each heater's power when on, W (mean power = duty × it)
  Eigen::MatrixXd case_heater_duty;  ///< (c × h) duty of each heater in each orbit case (1 row without an orbit), –
  HeatBalance heat;
  /// With optics that follow temperature: each node's absorbed solar/albedo and planet IR
  /// relative to the sweep's nominal ones, α(T)/α⁰ and ε(T)/ε⁰ (n×P); empty otherwise.
  Eigen::MatrixXd solar_load_scale, ir_load_scale;
  Eigen::MatrixXd temperature_stderr;       ///< (n×P) K, with a sweep; empty without
  std::string temperature_stderr_method;    ///< how it was propagated
  const Eigen::MatrixXd& temperature() const { return solve.temperature; }
};

/// A network-form run: the band solve of the case's initial exitance.
struct NetworkRunResult {
  RadiativeNetwork radiative;
  solver::BandSolution solution;           ///< one column, W/m²
  std::optional<ThermalSolution> thermal;  ///< steady state (P = 1), with `thermal:`
  StageTimings timings;
};

/// An imported run (import: {esatan_tmd}): the temperatures of the file's network.
struct ImportRunResult {
  ThermalSolution thermal;  ///< at the file's output times (times_s from its first)
  StageTimings timings;
};

/// What the exact view-factor method did (methods exact and auto).
struct ExactViewFactorStats {
  int patches = 0;
  std::int64_t pairs_culled = 0, pairs_hidden = 0, pairs_unoccluded = 0, pairs_occluded = 0;
  int sampled_rows = 0;  ///< rows left to ray casting
  double seconds = 0.0;  ///< the pair integrals (patches, clusters, plan and integration)
  std::int64_t pairs_by_quadrature = 0;  ///< unoccluded pairs settled by few-point rules
  /// Predicted time of the view-factor stage, s (auto's cost model: pair integrals over the
  /// threads plus the rows it casts); 0 when nothing was planned.
  double predicted_seconds = 0.0;
  std::vector<char> sampled_row_mask;  ///< per node: its row was left to rays
};

/// The design cases of a geometry run (docs/case-files.md, "Design cases"): what each is
/// and what it gave, all on the one eigendecomposition.
struct DesignCasesResult {
  std::vector<std::string> names, optics;  ///< per design case: its name and its optical set
  std::vector<int> orbit_case_start;       ///< first orbit case of each design case in the sweep, then their count
  std::vector<int> position_start;         ///< first position of each design case, then P
  std::vector<std::string> optics_names;   ///< every optical set, `base` first
  std::vector<solver::ExchangeFactors> optics_exchange;  ///< GR of every optical set after `base` (whose GR is the run's)
  /// Per design case and thermal node (c×n), K: the minimum over its positions, the
  /// time-weighted orbit mean and the maximum.
  Eigen::MatrixXd temperature_min, temperature_mean, temperature_max;
  /// (P) with thermal: each position's weight in its design case's time mean (timeWeights;
  /// they sum to 1 per design case), the weights of temperature_mean
  Eigen::VectorXd time_weight;
  Eigen::VectorXd envelope_min, envelope_max;            ///< per thermal node over every case, K
  Eigen::VectorXi envelope_min_case, envelope_max_case;  ///< which design case sets each
  std::vector<StageTimings> timings;                     ///< per design case (its sweep, loads, bands, thermal)
  int eigendecompositions = 0;  ///< of G, as counted by the run's timings: 1 serves every case, set and sample
  int band_cores = 0;                                    ///< k×k cores built (two per optical set and sample)
  int caseCount() const { return static_cast<int>(names.size()); }
};

/// `uncertainty:` the optical properties sampled on the same decomposition.
struct OpticalUncertaintyResult {
  std::vector<std::string> materials;  ///< the sensitivities' rows: every material with optics, sorted
  int samples = 0;
  /// (c×n) K: the 5th percentile of each sample's orbit minimum, the median of its orbit
  /// mean and the 95th percentile of its orbit maximum.
  std::array<Eigen::MatrixXd, 3> percentiles;
  std::vector<Eigen::MatrixXd> sample_min, sample_mean, sample_max;  ///< per sample (c×n), K
  /// d(orbit-mean T)/dα and /dε of each material (materials×n), K per unit: the mean over
  /// the design cases, then per case.
  Eigen::MatrixXd sensitivity_absorptivity, sensitivity_emissivity;
  std::vector<Eigen::MatrixXd> case_sensitivity_absorptivity, case_sensitivity_emissivity;
  double step = 0.0;     ///< the finite-difference half step of α and ε, –
  double clipped_absorptivity = 0.0, clipped_emissivity = 0.0;  ///< share of sampled node values clipped to [0, 1]
  double sample_seconds = 0.0;  ///< the samples alone, s
  double seconds = 0.0;         ///< sampling and sensitivities, s
};

/// Parts that turn during the orbit: what the configurations were.
struct ArticulationResult {
  std::vector<std::string> names;     ///< every drive: the moving ones, then the fixed ones
  Eigen::MatrixXd configuration_angle;  ///< (C × moving drives), deg: each configuration's angles
  std::vector<Eigen::MatrixXd> vertices;  ///< per configuration, the scene's vertices (nv×3), m
  std::vector<solver::ExchangeFactors> exchange;  ///< per configuration, GR of the base optics
  std::vector<int> update_rank;       ///< per configuration, the rank of its update of the pairs
  std::int64_t rays = 0;              ///< rays recast over all configurations
  int recast_rows = 0;                ///< rows recomputed in each configuration (integrated or cast)
  int integrated_rows = 0;            ///< of those, integrated by the exact method
  std::int64_t pairs = 0;             ///< patch pairs integrated over all configurations
};

/// A geometry-form run.
/// Writes the raw view-factor estimate (F before the correction and σ_F) into the output while
/// the run goes on; `dense`: whether the (n, n) datasets go beside the CSR groups, as for the
/// network the run will hold (OutputSettings::denseMatrices).
using RawEstimateWriter = std::function<void(const geometry::ViewFactorEstimate& raw, bool dense)>;

struct GeometryRunResult {
  Eigen::SparseMatrix<double, Eigen::RowMajor> raw_view_factors;  ///< before the correction, – (empty once written)
  /// σ (rays) or the error estimate (exact), –; empty once written when no later stage reads it
  solver::SparseRowMatrix view_factor_stderr;
  /// The raw F and σ_F went into the output during the run (runGeometryCase's write_raw).
  bool raw_estimate_written = false;
  double raw_estimate_write_seconds = 0.0;  ///< the time that took, s (not the view factors')
  Eigen::VectorXd row_stderr_max;  ///< each row's largest σ_F (whole when the rows are shared out), –
  Eigen::VectorXd lost_view_factor_stderr;  ///< σ of F_space + F_blocked per node, –
  geometry::ReciprocityCorrection correction;
  /// The solar band's own correction, when its specular optics differ from the IR band's.
  std::optional<geometry::ReciprocityCorrection> solar_correction;
  /// Specular tracing: rows traced (per band) and their rays.
  int specular_rows = 0;
  std::int64_t specular_rays = 0;
  std::optional<ExactViewFactorStats> exact;
  std::int64_t total_rays = 0;
  double rays_per_second = 0.0;
  Eigen::VectorXi triangle_node;  ///< node of each triangle: its front side's, else its back side's
  RadiativeNetwork radiative;
  solver::SolverSettings solver;           ///< the case's, with the error budget's tolerance
  std::optional<SweepResult> sweep;        ///< when the case has an orbit
  std::optional<ThermalSolution> thermal;  ///< P positions (1 without an orbit), with `thermal:`
  DesignCasesResult cases;
  std::optional<OpticalUncertaintyResult> optical_uncertainty;
  std::optional<ArticulationResult> articulation;  ///< with parts that turn during the orbit
  StageTimings timings;
};

}  // namespace radnet::cases
