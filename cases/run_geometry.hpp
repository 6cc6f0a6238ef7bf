#pragma once
// The pipeline of a geometry case: scene → view factors (ray casting or contour
// integration) → reciprocity/closure correction → network → eigenpairs → exchange factors.
#include "cases/geometry_case.hpp"
#include "cases/output.hpp"
#include "geometry/reciprocity.hpp"
#include "orbits/loads.hpp"
#include "solver/exchange.hpp"
#include "solver/thermal.hpp"

#include <iosfwd>
#include <memory>
#include <optional>

namespace radnet::cases {

struct GeometryRunResult {
  Eigen::MatrixXd raw_view_factors;  ///< before the correction, –
  Eigen::MatrixXd view_factor_stderr;  ///< σ of the raw estimate (MC) or quadrature error estimate (contour), –
  geometry::ReciprocityCorrection correction;
  std::unique_ptr<solver::Network> network;
  solver::EigenPairs pairs;
  solver::ExchangeFactors exchange;
  std::string exchange_method;
  /// Orbit sweep (present when the case has an orbit).
  struct Sweep {
    std::vector<orbits::SweepPosition> positions;  ///< of every orbit case, one after another
    std::vector<int> case_start;                   ///< first position of each case, then P
    std::vector<std::string> case_labels;
    orbits::EnvironmentLoads irradiance;  ///< external irradiances, W/m² (n×P)
    Eigen::MatrixXd absorbed_solar, absorbed_albedo, absorbed_earth_ir;  ///< absorbed after interreflection, W (n×P)
    Eigen::MatrixXd exitance_solar;  ///< solar-band exitance (direct + albedo), W/m² (n×P)
    double solar_residual = 0.0, ir_residual = 0.0;  ///< band-solve residuals with the full G
    int solar_refine_iterations = 0, ir_refine_iterations = 0;
    double energy_balance_error = 0.0;  ///< max over positions of |in − absorbed − lost| / in, solar band
  };
  std::optional<Sweep> sweep;
  /// Temperatures (n×P; P = 1 without an orbit), K, when the case has `thermal:`.
  std::optional<solver::ThermalResult> thermal;
  std::int64_t total_rays = 0;
  double rays_per_second = 0.0;
  Timings timings_s;
};

/// Runs the case. @throws NumericalError (exit 3)
GeometryRunResult runGeometryCase(const GeometryCase& c, bool show_progress, std::ostream& progress);

void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, const std::string& path);
void printGeometrySummary(const GeometryCase& c, const GeometryRunResult& r, std::ostream& out);
std::optional<double> lookupGeometryResult(const GeometryRunResult& r, const Expectation& x);

}  // namespace radnet::cases
