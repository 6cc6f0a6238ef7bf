#include "geometry/rays/ray_caster.hpp"

#include "geometry/scene/open_sides.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

namespace radnet::geometry {

namespace {

std::vector<std::array<Vec3, 3>> sceneTriangles(const Scene& scene) {
  std::vector<std::array<Vec3, 3>> triangles;
  triangles.reserve(scene.faces().size());
  for (const Face& f : scene.faces()) triangles.push_back(f.v);
  return triangles;
}

}  // namespace

RayCaster::RayCaster(const Scene& scene) : scene_(scene), bvh_(sceneTriangles(scene)) {
  side_nodes_.reserve(scene.faces().size());
  for (const Face& f : scene.faces()) side_nodes_.push_back({f.front_node, f.back_node});
  double max_coord = 0.0;
  for (const Face& f : scene.faces())
    for (const auto& v : f.v) max_coord = std::max(max_coord, v.cwiseAbs().maxCoeff());
  // A point interpolated on a triangle carries a rounding error of a few ulps of the
  // largest coordinate; 64 ulps leaves a safe margin and stays far below any feature size.
  offset_scale_ = 64.0 * std::numeric_limits<double>::epsilon() * std::max(max_coord, 1e-300);
}

const std::vector<std::uint8_t>& RayCaster::openSides() const {
  std::call_once(open_once_, [this] { open_sides_ = geometry::openSides(scene_); });
  return open_sides_;
}

Vec3 RayCaster::offsetOrigin(const Vec3& point, const Vec3& side_normal) const {
  return point + offset_scale_ * side_normal;
}

Hit RayCaster::firstHit(const Vec3& origin, const Vec3& dir, int skip) const {
  const TriangleBvh::Hit hit = bvh_.firstHit(origin, dir, skip);
  Hit out;
  if (hit.triangle < 0) return out;
  out.face = hit.triangle;
  out.distance = hit.t;
  out.front = hit.front;
  return out;
}

bool RayCaster::occluded(const Vec3& origin, const Vec3& dir, int skip) const {
  return bvh_.anyHit(origin, dir, skip);
}

}  // namespace radnet::geometry
