#pragma once
// Meshes as CAD and FE tools write them (docs/geometry.md, "Meshes from CAD and FE models"):
// placed by a transform, cleaned of what carries no area (degenerate and repeated triangles),
// their cracks closed where narrower than a weld tolerance, and measured for what the user must
// hear about at once: edges wound against their neighbour, edges of three or more triangles,
// the cracks left open, a (nearly) closed body whose fronts face inward, a size that says the
// file is in millimetres.
#include "geometry/scene/scene.hpp"

#include <Eigen/Geometry>

#include <limits>

namespace radnet::geometry {

/// Vertices of one mesh closer than this fraction of its bounding-box diagonal are welded
/// into one (the first seen): STL files store floats (7 digits), and CAD exporters repeat a
/// vertex per face, so a crack narrower than this is round-off, not a gap.
inline constexpr double kMeshWeldTolerance = 1e-6;
/// A mesh is nearly closed when the holes its open edges bound add up to at most this share
/// of its area (a cracked body; a plate, a tube or a half-open box are not).
inline constexpr double kNearlyClosedHoleShare = 1e-3;

/// What cleaning one mesh found. `first_*` number the file's faces (TriangleSoup::element),
/// 0-based, as the file holds them.
struct MeshReport {
  int welded_vertices = 0;  ///< vertices moved onto another within the weld tolerance
  int degenerate = 0, first_degenerate = -1;  ///< dropped: no area
  int duplicate = 0, first_duplicate = -1;    ///< dropped: the same corners with the same winding again
  int wound_against = 0, first_wound_against = -1;  ///< edges two triangles run the same way along
  int non_manifold_edges = 0;                       ///< edges of three or more triangles
  int open_edges = 0;                               ///< edges of one triangle (after welding)
  double open_length_m = 0.0;                       ///< their total length
  double hole_area_m2 = 0.0;  ///< the holes' area: per loop of open edges, the area it bounds or its
                              ///< length × the distance across to the next loop (a crack), the smaller
  double area_m2 = 0.0;       ///< the kept triangles' area
  bool nearly_closed = false;        ///< hole_area ≤ kNearlyClosedHoleShare · area, winding consistent
  double enclosed_volume_m3 = 0.0;   ///< signed (divergence theorem): negative when the fronts face inward
  double extent_m = 0.0;             ///< longest side of the bounding box
  double shortest_edge_m = std::numeric_limits<double>::infinity();
};

/// Welds, drops degenerate and duplicate triangles (keeping TriangleSoup::element aligned) and
/// measures the rest. @param weld_tolerance_m absolute; ≤ 0: kMeshWeldTolerance × diagonal
/// @throws GeometryError when a vertex is not finite or an index is out of range
MeshReport cleanMesh(TriangleSoup& soup, double weld_tolerance_m = 0.0);

/// p ↦ rotation p + translation for every vertex (and nominal point).
void transformMesh(TriangleSoup& soup, const Eigen::Matrix3d& rotation, const Vec3& translation);

/// Reverses every triangle's winding (so its front becomes its back).
void flipWinding(TriangleSoup& soup);

}  // namespace radnet::geometry
