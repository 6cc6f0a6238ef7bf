#pragma once
// NASTRAN bulk data as structures teams hand it over (docs/geometry.md, "NASTRAN bulk data"):
// GRID (positions in the basic system or a CORD2R), CTRIA3 and CQUAD4 shells, PSHELL and
// MAT4 for shell thickness and conductivity, INCLUDE; small field (8 characters), large field
// (`GRID*`, 16 characters, `*` continuations) and free field (commas). Other cards are counted
// and listed once, never fatal. The surface is grouped by property id (PID).
#include "geometry/scene/mesh_io.hpp"

#include <map>
#include <string>
#include <vector>

namespace radnet::geometry {

/// A CQUAD4 is refused when a corner lies farther than this fraction of its longest diagonal
/// from the plane through the other three (it would not be one flat element).
inline constexpr double kMaxQuadWarp = 1e-3;

struct NastranModel {
  /// One group per PID, named by it, in increasing PID order; each triangle's element is its
  /// EID (a CQUAD4 gives two triangles of one EID).
  std::vector<MeshGroup> groups;
  std::map<int, double> thickness_m;     ///< PSHELL T per PID (file units × scale); 0: blank
  /// The MAT4 card of a PID's PSHELL MID1 (K, CP, RHO as the file gives them; 0: blank).
  struct Mat4 {
    long mid = 0;
    double conductivity = 0.0, specific_heat = 0.0, density = 0.0;
  };
  std::map<int, Mat4> material;          ///< per PID whose MID1 has a MAT4
  std::map<std::string, int> skipped;    ///< cards read past, by name, with their count
};

/// Reads `path` (and its INCLUDEs, relative to the including file) in file units × `scale`.
/// @throws GeometryError naming file:line for a bad card or field, the element id for an
///         element with a missing grid or property, a warped quad or a cycle of CORD2R systems
NastranModel readNastran(const std::string& path, double scale);

}  // namespace radnet::geometry
