#pragma once
// A run's result files: the HDF5 file (docs/hdf5-layout.md) and, for geometry cases, the
// XDMF sidecar for ParaView. Both are written to temporary names and renamed at the end.
#include "cases/config/geometry_case.hpp"
#include "cases/config/network_case.hpp"
#include "cases/pipeline/results.hpp"

#include <string>

namespace radnet::cases {

void writeNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const std::string& path);

/// Writes `path` and its sidecar (same stem, .xmf), renamed after the HDF5 file.
void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, const std::string& path);

}  // namespace radnet::cases
