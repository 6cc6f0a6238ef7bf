#pragma once
// A run's result files: the HDF5 file (docs/hdf5-layout.md) and, for geometry cases, the
// XDMF sidecar for ParaView. Both are written to temporary names and renamed at the end.
#include "cases/config/geometry_case.hpp"
#include "cases/config/import_case.hpp"
#include "cases/config/network_case.hpp"
#include "cases/output/hdf5_writer.hpp"
#include "cases/output/shared_matrices.hpp"  // the other MPI ranks' part of writing (writeSharedMatrices)
#include "cases/pipeline/results.hpp"

#include <string>
#include <vector>

namespace radnet::cases {

/// `warnings`: the run's warnings, kept in /report/warnings (an empty dataset when none).
void writeNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const std::string& path,
                        const std::vector<std::string>& warnings);

/// An imported case's result: its nodes (all lumped, area 0, /nodes/label), temperatures and heat flows.
void writeImportedResult(const ImportedCase& c, const ImportRunResult& r, const std::string& path,
                         const std::vector<std::string>& warnings);

/// Writes `path` and its sidecar (same stem, .xmf), published together.
void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, const std::string& path,
                         const std::vector<std::string>& warnings);
/// What writes the raw estimate into `h5` while the run goes on (runGeometryCase's write_raw).
RawEstimateWriter rawEstimateInto(Hdf5Writer& h5);
/// The same into `h5`, opened on `path` before the run (which may have written its raw
/// estimate there: runGeometryCase's write_raw).
void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, Hdf5Writer& h5, const std::string& path,
                         const std::vector<std::string>& warnings);

}  // namespace radnet::cases
