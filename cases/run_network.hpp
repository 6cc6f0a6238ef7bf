#pragma once
// The pipeline of a network-only case: network → one eigendecomposition → band solve
// (+ exchange factors when emissivities are given) → HDF5 and a summary table.
#include "cases/network_case.hpp"
#include "solver/exchange.hpp"
#include "solver/low_rank_solver.hpp"
#include "solver/thermal.hpp"

#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

struct NetworkRunResult {
  std::unique_ptr<solver::Network> network;
  solver::EigenPairs pairs;
  solver::BandSolution solution;               ///< one column: the case's initial exitance
  std::optional<solver::ExchangeFactors> exchange;
  std::string exchange_method;                 ///< "dense LU" or "low rank"
  std::optional<solver::ThermalResult> thermal;  ///< steady state (n×1), K, with `thermal:`
  std::vector<std::pair<std::string, double>> timings_s;  ///< stage name, wall seconds
};

/// Runs the case. @throws NumericalError (exit 3) on a failed eigensolve or band solve
NetworkRunResult runNetworkCase(const NetworkCase& c, std::ostream& progress);

/// Writes the result atomically to `path` (see docs/hdf5-layout.md).
void writeNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const std::string& path);

/// The per-node table and the run's figures, on stdout.
void printNetworkSummary(const NetworkCase& c, const NetworkRunResult& r, std::ostream& out);

/// The computed value an expectation refers to, if the run has it.
std::optional<double> lookupNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const Expectation& x);

}  // namespace radnet::cases
