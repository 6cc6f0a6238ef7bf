#pragma once
// XDMF 3 sidecar for ParaView: the mesh from /geometry and per-triangle values as a time
// series over the orbit (one grid per sweep position, hyperslabs into (P, nt) datasets).
#include "cases/output/hdf5_writer.hpp"
#include "cases/pipeline/results.hpp"

#include <string>
#include <vector>

namespace radnet::cases {

struct XdmfAttribute {
  std::string name;     ///< as ParaView shows it
  std::string dataset;  ///< HDF5 path: (nt) for static values, (P, nt) for a time series
  bool per_position;
  bool integer = false;
};

/// The XDMF text. `h5_name` is the HDF5 file as the .xmf refers to it (same directory).
std::string xdmfText(const std::string& h5_name, long vertices, long triangles, const std::vector<double>& times_s,
                     const std::vector<XdmfAttribute>& attributes);

/// Writes the per-triangle copies of node values that the sidecar shows into /xdmf: a
/// triangle shows its node (GeometryRunResult::triangle_node). Returns what it wrote.
std::vector<XdmfAttribute> writeXdmfCellValues(Hdf5Writer& h5, const GeometryRunResult& r);

/// The sidecar's path beside the HDF5 file: same folder and stem, extension .xmf.
std::string xdmfPathFor(const std::string& h5_path);

/// Writes `text` to `path` through a temporary file and a rename.
void writeTextAtomically(const std::string& path, const std::string& text);

}  // namespace radnet::cases
