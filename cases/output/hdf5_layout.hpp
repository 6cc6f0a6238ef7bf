#pragma once
// One writer per HDF5 group of docs/hdf5-layout.md, shared by both case forms.
#include "cases/config/geometry_case.hpp"
#include "cases/config/thermal_settings.hpp"
#include "cases/output/hdf5_writer.hpp"
#include "cases/pipeline/results.hpp"

#include <optional>
#include <string>

namespace radnet::cases {

/// /meta: program, version, case name, creation time, the case file and its includes.
void writeMeta(Hdf5Writer& h5, const std::string& case_name, const std::string& case_yaml,
               const IncludedFiles& included = {});
/// /nodes/{name, area, lumped}: every node of the case, the radiative ones first, then the
/// lumped nodes of the thermal model (area 0).
void writeNodes(Hdf5Writer& h5, const RadiativeNetwork& radiative, const std::optional<ThermalSolution>& thermal);
/// /network/{view_factors, space_view_factor, conductance}, /network/{radiative_exchange,
/// gr_space} when known, /eigen/{values, vectors}: the radiative nodes only.
/// The (n,n) datasets only as `output` says (kDenseOutputMaxNodes); every matrix also in CSR
/// under /network/sparse and GR as /network/radiative_exchange_factors (hdf5_matrices.hpp).
void writeRadiativeNetwork(Hdf5Writer& h5, const RadiativeNetwork& radiative, const OutputSettings& output);
/// The node count of the written file: radiative plus lumped nodes.
Eigen::Index nodeCount(const RadiativeNetwork& radiative, const std::optional<ThermalSolution>& thermal);
/// `values` (rows: the radiative nodes) with zero rows for the lumped nodes up to `rows`.
Eigen::MatrixXd padNodes(const Eigen::MatrixXd& values, Eigen::Index rows);
/// /geometry/{vertices, triangles, triangle_node, triangle_front_node, triangle_back_node}.
void writeGeometry(Hdf5Writer& h5, const geometry::Scene& scene, const geometry::SeamReport& seams,
                   const Eigen::VectorXi& triangle_node);
/// /network/{view_factor_stderr, view_factors_raw, blocked_view_factor} and how F was made.
/// The raw F (`view_factors_raw`) and σ_F (`view_factor_stderr`, on the raw F's pattern) under
/// /network, with their (n, n) datasets when `dense` (runGeometryCase writes them early).
void writeRawViewFactors(Hdf5Writer& h5, const geometry::ViewFactorEstimate& raw, bool dense);
void writeViewFactorEstimate(Hdf5Writer& h5, const GeometryRunResult& r, ViewFactorMethod method,
                             const OutputSettings& output);
/// /orbit, /loads and /solution/exitance_solar of a sweep (zero for lumped nodes, up to
/// `nodes` columns), its residuals in /report.
void writeSweep(Hdf5Writer& h5, const SweepResult& sweep, Eigen::Index nodes);
/// /solution/temperature (P, n) K with its mode, /nodes/{capacitance, dissipation}, and
/// /solution/heat/* (P, n) W: every node's heat flows by kind (the environment's from the
/// sweep, zero without one), with the largest imbalance in /report.
void writeTemperatures(Hdf5Writer& h5, const ThermalSolution& thermal, const ThermalSettings& settings,
                       const SweepResult* sweep);
/// /uncertainty/absorbed_power (P, n) W and its parts by source, /uncertainty/temperature
/// (P, n) K when temperatures were computed, and the error budget's split in /report.
void writeUncertainty(Hdf5Writer& h5, const GeometryCase& c, const GeometryRunResult& r, Eigen::Index nodes);
/// /cases, /orbit/design_case, /optics/<set>, /solution/case_temperature_*,
/// /solution/envelope and the cases' /report attributes (docs/hdf5-layout.md).
void writeDesignCases(Hdf5Writer& h5, const GeometryCase& c, const GeometryRunResult& r);
/// /uncertainty/temperature_percentiles, the samples and the sensitivities of `uncertainty:`.
void writeOpticalUncertainty(Hdf5Writer& h5, const GeometryCase& c, const OpticalUncertaintyResult& u);
/// /articulation: the drives' names and angles per position, the configurations' angles, GR
/// and vertices, and their /report attributes (docs/hdf5-layout.md).
void writeArticulation(Hdf5Writer& h5, const GeometryCase& c, const GeometryRunResult& r);
/// /report time_<stage>_s attributes.
void writeTimings(Hdf5Writer& h5, const StageTimings& timings);

}  // namespace radnet::cases
