#pragma once
// XDMF 3 sidecars for ParaView (docs/paraview.md). Both of ParaView's readers (the classic
// "XDMF Reader" and the "Xdmf3 Reader S/T") open them with every field:
//   - one temporal collection per orbit case; each step is a spatial collection of blocks:
//     "front" (the front sides of triangles whose front is a node), "back" (the back sides of
//     two-sided or back-only triangles, winding reversed so its normals point out of that
//     side) and "inactive" (occluders: geometry only);
//   - every value is a plain 1-D dataset per block and position under /xdmf (no hyperslabs:
//     the Xdmf3 readers drop hyperslab fields as "unrecognized array type");
//   - every HDF reference is the file name alone, which both readers resolve beside the .xmf.
// One orbit case: <stem>.xmf. Several: <stem>.<case label>.xmf each, and <stem>.xmf with the
// geometry and static fields (node, area, the temperature envelope).
#include "cases/output/hdf5_writer.hpp"
#include "cases/pipeline/results.hpp"
#include "geometry/scene/scene.hpp"

#include <string>
#include <utility>
#include <vector>

namespace radnet::cases {

/// One block of triangles shown with the values of one side.
struct XdmfBlock {
  std::string name;           ///< "front", "back" or "inactive"
  Eigen::MatrixXi triangles;  ///< (m × 3) vertex indices, 0-based
  Eigen::VectorXi node;       ///< node of each triangle on this side, −1: none
};

/// A cell field: node values spread onto every block's triangles.
struct XdmfField {
  std::string name;         ///< as ParaView shows it, with units
  std::string key;          ///< dataset leaf name under /xdmf/<block>/
  Eigen::MatrixXd by_node;  ///< (n × P) per position, or (n × 1) static
  bool per_position = false;
};

/// One time series (one .xmf file): the positions it shows and their times.
struct XdmfSeries {
  std::string label;           ///< the orbit case's label ("" for a run without orbit cases)
  std::string file;            ///< .xmf path
  std::vector<int> positions;  ///< global position (column) indices
  std::vector<double> times_s;
};

/// What was written to /xdmf, for the text of each file.
struct XdmfPlan {
  long vertices = 0;
  std::vector<XdmfBlock> blocks;
  std::vector<XdmfField> fields;  ///< values dropped (only names and kinds are kept)
  std::vector<XdmfSeries> series;
  std::string overview_file;      ///< <stem>.xmf when there are several series, else ""
  /// Parts that turn: each position's configuration (its vertices /xdmf/vertices/configuration_<k>,
  /// configuration 0 /geometry/vertices); empty: the one geometry throughout.
  std::vector<int> position_configuration;
};

/// The blocks of a scene: front sides, back sides (reversed), inactive triangles; empty ones
/// are left out.
std::vector<XdmfBlock> xdmfBlocks(const geometry::Scene& scene);

/// Writes /xdmf (blocks, per-position fields, the file list) and returns the plan.
XdmfPlan writeXdmfData(Hdf5Writer& h5, const geometry::Scene& scene, const GeometryRunResult& r,
                       const std::string& h5_path);

/// The text of one series file (`series` < 0: the static overview).
std::string xdmfText(const XdmfPlan& plan, int series, const std::string& h5_name);

/// Every file of the plan with its text: (path, text), for Hdf5Writer::commit to publish with
/// the HDF5 file.
std::vector<std::pair<std::string, std::string>> xdmfFiles(const XdmfPlan& plan, const std::string& h5_path);

/// The sidecar's path beside the HDF5 file: same folder and stem, extension .xmf.
std::string xdmfPathFor(const std::string& h5_path);

}  // namespace radnet::cases
