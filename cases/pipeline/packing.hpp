#pragma once
// A design case's thermal outcome as bytes and back, to move it between MPI ranks
// (cases/pipeline/distributed.hpp): every field, in a fixed order, bit for bit. A field
// added to ThermalSolution must be added to both functions (the MPI test compares every
// dataset of a 2-rank run with one process, so a forgotten field shows there).
#include "cases/pipeline/results.hpp"
#include "cases/pipeline/stages.hpp"

#include <string>

namespace radnet::cases {

/// What a design case's thermal solve gives: the solution, what it printed, how long it took.
struct ThermalOutcome {
  ThermalSolution thermal;
  std::string log;        ///< its progress lines and warnings
  StageTimings timings;   ///< its stages (thermal, uncertainty), s
};

std::string packThermal(const ThermalOutcome& outcome);
/// @throws std::runtime_error when the bytes end early or run on (a version mismatch)
ThermalOutcome unpackThermal(const std::string& bytes);

}  // namespace radnet::cases
