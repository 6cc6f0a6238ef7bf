#pragma once
// What a turning part can reach: the solid its triangles sweep about a drive's axis over a
// full turn, bounded by a cylinder about that axis. A node whose every triangle has this
// cylinder wholly behind its plane can see nothing of the part at any angle, nor anything
// the part could hide from it: its row of F does not change as the part turns.
#include "geometry/scene/scene.hpp"

#include <vector>

namespace radnet::geometry {

/// The cylinder about the line point + t axis holding every angle of some surfaces.
struct SweptCylinder {
  Vec3 point = Vec3::Zero();  ///< on the axis, m
  Vec3 axis = Vec3::UnitX();  ///< unit
  double axial_min = 0.0, axial_max = 0.0;  ///< t range of the surfaces' vertices, m
  double radius = 0.0;                      ///< largest distance of a vertex from the axis, m
  /// max over the cylinder of n · x, for a unit n (its support function), m.
  double support(const Vec3& n) const;
  /// Whether the half-line origin + t dir, t ≥ 0, meets the (solid) cylinder.
  bool meets(const Vec3& origin, const Vec3& dir) const;
};

/// The cylinder swept by `surfaces` (indices into Scene::surfaceNames()) about the axis.
SweptCylinder sweptCylinder(const Scene& scene, const std::vector<int>& surfaces, const Vec3& point, const Vec3& axis);

/// Per node, 1 when a triangle of its side has part of `swept` in front of its plane (by more
/// than 1e-9 of the scene's extent): the nodes whose rows may change as the part turns.
std::vector<char> nodesFacing(const Scene& scene, const SweptCylinder& swept);

}  // namespace radnet::geometry
