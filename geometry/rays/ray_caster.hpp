#pragma once
// First-hit ray casting through a CGAL AABB tree over the scene's triangles. The tree is
// built once, eagerly, so that concurrent queries from many threads are safe.
#include "geometry/scene/scene.hpp"

#include <array>
#include <memory>
#include <utility>
#include <vector>

namespace radnet::geometry {

struct Hit {
  int face = -1;          ///< scene face index, −1: nothing hit (space)
  double distance = 0.0;  ///< m
  bool front = false;     ///< the ray arrived on the face's front side
};

class RayCaster {
 public:
  /// Triangles longer than this many times the scene's median longest edge enter the tree in
  /// pieces (the hit is still reported on the whole face): see ray_caster.cpp.
  static constexpr double kSplitLength = 2.0;
  static constexpr int kSplitDepth = 8;  ///< at most 2^8 pieces a triangle
  using TreeInput = std::vector<std::pair<std::array<Vec3, 3>, int>>;

  explicit RayCaster(const Scene& scene);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  /// The first triangle hit by the ray origin + t dir, t > 0, ignoring face `skip`.
  /// @param dir unit direction
  Hit firstHit(const Vec3& origin, const Vec3& dir, int skip = -1) const;

  /// A ray origin on face `face`, offset to the side `side_normal` points to by a bound on
  /// the rounding error of the point (pbrt's approach), so the ray cannot re-hit its own face.
  Vec3 offsetOrigin(const Vec3& point, const Vec3& side_normal) const;

  const Scene& scene() const { return scene_; }

 private:
  struct Tree;
  const Scene& scene_;
  std::unique_ptr<Tree> tree_;
  double offset_scale_ = 0.0;
};

}  // namespace radnet::geometry
