#pragma once
// radnet export --format tmd: a result as the TMD file ESATAN-TMS writes (docs/export.md,
// "TMD out"), every output time of one design case, so that ESATAN post-processors
// (pycanha, MATLAB readers) read radnet's run as they read ESATAN's.
#include "cases/output/export.hpp"

#include <string>

namespace radnet::cases {

/// Writes the TMD of the design case `o.design_case` (every one of its positions) to `out`,
/// atomically. @throws InputError (exit 2) for a result without temperatures or whose
/// positions' times do not increase; OutputError (exit 4) when it cannot be written
void writeTmdExport(const Hdf5Reader& h5, const ExportOptions& o, const std::string& out);

}  // namespace radnet::cases
