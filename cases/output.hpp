#pragma once
// HDF5 groups shared by every kind of run (layout in docs/hdf5-layout.md).
#include "cases/hdf5_writer.hpp"
#include "solver/eigenpairs.hpp"
#include "solver/exchange.hpp"
#include "solver/network.hpp"

#include <string>
#include <utility>
#include <vector>

namespace radnet::cases {

using Timings = std::vector<std::pair<std::string, double>>;

/// /meta: program, version, case name, creation time and the case file itself.
void writeMeta(Hdf5Writer& h5, const std::string& case_name, const std::string& case_yaml);
/// /nodes/name, /nodes/area and /network/{view_factors, space_view_factor, conductance}.
void writeNetwork(Hdf5Writer& h5, const solver::Network& net);
/// /network/{radiative_exchange, gr_space}.
void writeExchange(Hdf5Writer& h5, const solver::ExchangeFactors& ex, const std::string& method);
/// /eigen/{values, vectors} and their attributes.
void writeEigen(Hdf5Writer& h5, const solver::EigenPairs& pairs);
/// /report time_<stage>_s attributes.
void writeTimings(Hdf5Writer& h5, const Timings& timings);

/// The case's eigenpairs for both bands (ρ = 1 − ε and the band's own ρ): the rank rule
/// bounds ‖S‖ by the larger reflectance over A of the two.
solver::EigenPairs decomposeForBands(const solver::Network& net, const Eigen::VectorXd& max_reflectance,
                                     int rank, double tolerance, int max_rank, solver::EigenMethod method);

/// The exchange factors of a run: exact by dense LU when the case asks for full accuracy
/// and n ≤ 3000 (O(n³)), else E V C Vᵀ E from the eigenpairs. Sets `method` to say which.
/// @throws NumericalError when they cannot be formed (e.g. a lossless closed cavity)
solver::ExchangeFactors computeExchangeFactors(const solver::Network& net, const solver::EigenPairs& pairs,
                                               const Eigen::VectorXd& emissivity, bool full_accuracy,
                                               std::string& method);

/// Wall time of a stage.
class StageTimer {
 public:
  StageTimer();
  double seconds() const;

 private:
  double start_;
};

}  // namespace radnet::cases
