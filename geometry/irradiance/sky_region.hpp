#pragma once
// Where a flat node's sky can be blocked at all, for the sky kernel's rays
// (geometry/irradiance/sky_kernel): cosine-weighted directions about the normal n are the
// unit disc of the tangent plane lifted to the hemisphere (Malley), uniform in area. The
// directions in which some triangle lies in front of the node, seen from anywhere on it,
// fit in a region of that disc: an annular sector r ∈ [r0, r1], φ ∈ [φ0, φ0 + Δφ]
// (r = sin θ), or up to eight disjoint rectangles in the disc's coordinates (x, y) =
// (ω·t0, ω·t1), whichever is smaller. Rays drawn uniformly in the region's area (affine
// in the same two Sobol coordinates, so a node cast again still resumes its stream) each
// stand for share / N of the hemisphere, share = the region's area over π; a rectangle's
// points outside the disc are rays that meet nothing, counted and not traced. The rays
// outside the region are open for certain and need no tracing. The estimate stays
// unbiased; its variance falls by the share (a wing cell 2 m from the bus sees its
// blockers in a tenth of its disc).
//
// The region is conservative: the triangles are bounded by a tree of spheres, a sphere in
// front of the node's plane is seen from the node's bounding sphere within the cone of
// half-angle α = asin((r_node + r_sphere) / distance) (every direction from a point of one
// ball to a point of the other). A cone's θ extent is its axis' θ ± α, its φ extent
// asin(sin α / sin θ_axis) either side of its axis (the tangents from the pole); its x
// extent [cos(min(π, β + α)), cos(max(0, β − α))], β the axis' angle from t0 (and y's from
// t1). The sector merges the cones' extents (azimuths by the complement of their largest
// gap); the rectangles are the cones' boxes split where they separate along x or y.
// Triangles within the ray origins' offset of the node's plane cannot be met by a ray
// leaving it upward, and are left out (the node's own face and its coplanar neighbours).
#include "geometry/scene/scene.hpp"

#include <array>
#include <utility>
#include <vector>

namespace radnet::geometry {

struct SkyRegion {
  bool whole = true;  ///< true: the rays cover the hemisphere (no region)
  Vec3 n = Vec3::UnitZ(), t0 = Vec3::UnitX(), t1 = Vec3::UnitY();  ///< the node's frame
  double r0_squared = 0.0, r1_squared = 1.0;  ///< sin² of the sector's polar angles
  double phi0 = 0.0, phi_span = 2.0 * M_PI;   ///< rad, from t0 towards t1
  /// Rectangles of the disc instead of the sector (box_count > 0): {x0, x1, y0, y1}, disjoint.
  static constexpr int kMostBoxes = 8;
  std::array<std::array<double, 4>, kMostBoxes> boxes{};
  int box_count = 0;
  /// The cosine-weighted share of the hemisphere the rays are drawn from, –.
  double share() const;
  /// The direction at unit-square coordinates (u2, u3), uniform in the region's area; false
  /// for a rectangle's point outside the disc (a ray that meets nothing).
  bool direction(double u2, double u3, Vec3& unit_direction) const;
  /// Whether a unit direction lies in the region.
  bool contains(const Vec3& unit_direction) const;
};

/// The shortest arc covering arcs of the circle given as (centre, half-width) (rad): its
/// start in [0, 2π) and its span, the complement of the largest gap between them (no gap,
/// a half-width ≥ π or no arc: (0, 2π)).
std::pair<double, double> coveringArc(const std::vector<std::pair<double, double>>& centre_half);

/// A tree of bounding spheres over every triangle of a scene (occluders included), built
/// once, asked for each node's sector.
class BlockerSpheres {
 public:
  /// `origin_offset_m`: how far the rays' origins stand off their triangle (RayCaster).
  BlockerSpheres(const Scene& scene, double origin_offset_m);
  /// The node's region, whole when the node is not flat (several normals or planes), a
  /// blocker touches its bounding sphere, or the region's share exceeds `max_share`.
  SkyRegion regionOf(int node, double max_share = 0.9) const;
  /// Both regions regionOf chooses between: the sector and the rectangles (whole when the
  /// node has none).
  std::array<SkyRegion, 2> candidates(int node) const;

 private:
  struct Ball {
    Vec3 centre, lo, hi;  ///< m: the bounding sphere's centre, and the box it came from
    double radius = 0.0;
    int left = -1, right = -1;  ///< children; a leaf holds one triangle
  };
  /// A flat node: its normal, the height below which a triangle cannot be met, its
  /// bounding sphere.
  struct FlatNode {
    Vec3 n, centre;
    double below = 0.0, radius = 0.0;
  };
  const Scene& scene_;
  double offset_m_ = 0.0;
  std::vector<Ball> balls_;
  int build(std::vector<int>& faces, int begin, int end);
  bool flatNode(int node, FlatNode& out) const;
  /// The cones (unit axis, half-angle) holding every triangle in front of the node; false
  /// when one touches its bounding sphere or the descent grows too long.
  bool cones(const FlatNode& node, std::vector<std::pair<Vec3, double>>& out) const;
};

}  // namespace radnet::geometry
