#pragma once
// First-hit and any-hit ray casting through a bounding volume hierarchy over the scene's
// triangles (rays/bvh.hpp). The hierarchy is built once, in the constructor, so concurrent
// queries from many threads are safe.
#include "geometry/rays/bvh.hpp"
#include "geometry/scene/scene.hpp"

#include <array>
#include <cstdint>
#include <mutex>
#include <vector>

namespace radnet::geometry {

struct Hit {
  int face = -1;          ///< scene face index, −1: nothing hit (space)
  double distance = 0.0;  ///< m
  bool front = false;     ///< the ray arrived on the face's front side
};

class RayCaster {
 public:
  explicit RayCaster(const Scene& scene);
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// The first triangle hit by the ray origin + t dir, t > 0, ignoring face `skip`.
  /// @param dir unit direction
  Hit firstHit(const Vec3& origin, const Vec3& dir, int skip = -1) const;
  /// Whether the ray origin + t dir, t > 0, hits any face but `skip` (shadow rays: stops at
  /// the first triangle found, nearest or not).
  bool occluded(const Vec3& origin, const Vec3& dir, int skip = -1) const;

  /// A ray origin on face `face`, offset to the side `side_normal` points to by a bound on
  /// the rounding error of the point (pbrt's approach), so the ray cannot re-hit its own face.
  Vec3 offsetOrigin(const Vec3& point, const Vec3& side_normal) const;
  /// How far offsetOrigin moves a point, m.
  double originOffset() const { return offset_scale_; }

  /// The node of the side a hit arrived on: −1 when that side is inactive or nothing was hit.
  /// (A compact copy of the faces' nodes: a ray's tally reads no 120-byte face.)
  int nodeHit(const Hit& hit) const {
    return hit.face < 0 ? -1 : side_nodes_[static_cast<size_t>(hit.face)][hit.front ? 0 : 1];
  }

  const Scene& scene() const { return scene_; }
  /// Per face, which of its sides have nothing of the scene in front (scene/open_sides.hpp),
  /// found the first time a stage asks (the scene's hull: 0.07 s on a 100,002-node model) and
  /// kept for the others (the sky kernel, exact sunlight). Safe from many threads.
  const std::vector<std::uint8_t>& openSides() const;

 private:
  const Scene& scene_;
  TriangleBvh bvh_;
  std::vector<std::array<int, 2>> side_nodes_;  ///< per face: front node, back node (−1: inactive)
  double offset_scale_ = 0.0;
  mutable std::once_flag open_once_;
  mutable std::vector<std::uint8_t> open_sides_;
};

}  // namespace radnet::geometry
