#pragma once
// The console summary of a run on stdout: per-node tables and the run's figures.
#include "cases/config/geometry_case.hpp"
#include "cases/config/import_case.hpp"
#include "cases/config/network_case.hpp"
#include "cases/pipeline/results.hpp"

#include <iosfwd>

namespace radnet::cases {

/// Up to 40 nodes, or with `all_nodes`, every node has a row; beyond, each table shows its
/// extremes and one row per primitive (cases/output/node_table.hpp).
void printNetworkSummary(const NetworkCase& c, const NetworkRunResult& r, std::ostream& out, bool all_nodes = false);
void printImportedSummary(const ImportedCase& c, const ImportRunResult& r, std::ostream& out, bool all_nodes = false);
void printGeometrySummary(const GeometryCase& c, const GeometryRunResult& r, std::ostream& out,
                          bool all_nodes = false);

}  // namespace radnet::cases
