#pragma once
// The console summary of a run on stdout: per-node tables and the run's figures.
#include "cases/config/geometry_case.hpp"
#include "cases/config/network_case.hpp"
#include "cases/pipeline/results.hpp"

#include <iosfwd>

namespace radnet::cases {

void printNetworkSummary(const NetworkCase& c, const NetworkRunResult& r, std::ostream& out);
void printGeometrySummary(const GeometryCase& c, const GeometryRunResult& r, std::ostream& out);

}  // namespace radnet::cases
