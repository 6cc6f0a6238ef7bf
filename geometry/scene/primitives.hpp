#pragma once
// Surfaces as thermal engineers model them, tessellated into triangles. Front sides:
// u × v (rectangle), the corner order (quadrilateral, triangle), `normal` (disc), outward
// (cylinder, cone, sphere, box). Angles in degrees, lengths in metres.
//
// Curved primitives are "area-preserving": after tessellation the radial coordinates are
// scaled so that the facetted area equals the exact area of the curved surface, so node
// areas (and the reciprocity they imply, e.g. F_outer→inner = A_inner/A_outer for
// concentric spheres) do not carry the facetting error.
#include "geometry/scene/scene.hpp"

#include <array>
#include <optional>
#include <string>

namespace radnet::geometry {

/// Parallelogram origin + s u + t v, s, t ∈ [0, 1], split into nu × nv cells of two triangles.
TriangleSoup rectangle(const Vec3& origin, const Vec3& u, const Vec3& v, int nu, int nv);

/// Planar quadrilateral p0 p1 p2 p3 (in order), bilinear nu × nv grid.
/// @throws GeometryError when the corners are not coplanar (relative 1e-9) or the quad is not convex
TriangleSoup quadrilateral(const std::array<Vec3, 4>& corners, int nu, int nv);

/// Triangle a b c split into n² similar triangles.
TriangleSoup triangle(const Vec3& a, const Vec3& b, const Vec3& c, int n);

/// An angular sector [start, end] about an axis, with the direction of angle 0.
struct Sweep {
  double start_deg = 0.0;
  double end_deg = 360.0;
  std::optional<Vec3> reference;  ///< direction of angle 0 (projected onto the plane); default: any
};

/// Disc or annulus (inner_radius > 0), optionally a sector.
TriangleSoup disc(const Vec3& center, const Vec3& normal, double radius, double inner_radius, const Sweep& sweep,
                  int radial, int angular);

/// Cylinder wall from base_center to base_center + axis, outward front.
TriangleSoup cylinder(const Vec3& base_center, const Vec3& axis, double radius, const Sweep& sweep, int axial,
                      int angular);

/// Cone or frustum wall: radius base_radius at base_center, top_radius at base_center + axis; outward front.
TriangleSoup cone(const Vec3& base_center, const Vec3& axis, double base_radius, double top_radius, const Sweep& sweep,
                  int axial, int angular);

/// Sphere or spherical patch: polar angle θ ∈ [theta_min, theta_max] from `axis`, azimuth in `sweep`; outward front.
TriangleSoup sphere(const Vec3& center, double radius, const Vec3& axis, double theta_min_deg, double theta_max_deg,
                    const Sweep& sweep, int polar, int azimuthal);

/// The six faces of an axis-aligned box [origin, origin + size], outward fronts, in the
/// order +x, −x, +y, −y, +z, −z, each split n × n.
std::array<TriangleSoup, 6> boxFaces(const Vec3& origin, const Vec3& size, int n);
inline constexpr std::array<const char*, 6> kBoxFaceNames = {"+x", "-x", "+y", "-y", "+z", "-z"};

/// Total area of a soup, m².
double soupArea(const TriangleSoup& soup);

}  // namespace radnet::geometry
