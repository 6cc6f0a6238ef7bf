#pragma once
// The pipeline of a network-form case: network → one eigendecomposition → band solve of
// the initial exitance (+ exchange factors and steady temperatures when emissivities
// are given); and the pipeline of an imported case (its thermal network only).
#include "cases/config/import_case.hpp"
#include "cases/config/network_case.hpp"
#include "cases/pipeline/results.hpp"

#include <iosfwd>

namespace radnet::cases {

/// Runs the case. @throws NumericalError (exit 3) on a failed eigensolve or band solve
NetworkRunResult runNetworkCase(const NetworkCase& c, std::ostream& progress);

/// Runs an imported thermal network (no radiative node: its GR are given) at its file's
/// output times. @throws NumericalError (exit 3) when the temperatures cannot be solved
ImportRunResult runImportedCase(const ImportedCase& c, std::ostream& progress);

}  // namespace radnet::cases
