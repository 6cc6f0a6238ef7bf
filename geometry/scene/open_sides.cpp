#include "geometry/scene/open_sides.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace radnet::geometry {

namespace {

// The scene's extreme points and their bounding box: every vertex when the hull cannot be
// formed (fewer than four points, all on a line or a plane).
struct SceneExtent {
  std::vector<Vec3> vertices;
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  double tolerance = 0.0;  ///< m: what counts as on a plane

  explicit SceneExtent(const Scene& scene) {
    using Hull = CGAL::Exact_predicates_inexact_constructions_kernel;
    // Each vertex once (a face holds copies of its corners: three times the points, and the
    // hull of a 100,002-node model's 600 k copies took 0.27 s).
    std::vector<std::array<double, 3>> corners;
    corners.reserve(3 * scene.faces().size());
    for (const Face& f : scene.faces())
      for (const Vec3& v : f.v) corners.push_back({v.x(), v.y(), v.z()}), lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    std::sort(corners.begin(), corners.end());
    corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
    std::vector<Hull::Point_3> points;
    points.reserve(corners.size());
    for (const auto& c : corners) points.emplace_back(c[0], c[1], c[2]);
    tolerance = points.empty() ? 0.0 : 1e-9 * std::max(1.0, (hi - lo).norm());
    CGAL::Surface_mesh<Hull::Point_3> hull;
    if (points.size() >= 4) CGAL::convex_hull_3(points.begin(), points.end(), hull);
    if (hull.number_of_vertices() >= 3)
      for (const auto& p : hull.points()) vertices.emplace_back(p.x(), p.y(), p.z());
    else
      for (const auto& p : points) vertices.emplace_back(p.x(), p.y(), p.z());
  }

  // Whether every vertex lies on or behind the plane through `on` with normal `n`: the box
  // first (its farthest corner along n), then the hull's vertices, stopping at the first in
  // front.
  bool behind(const Vec3& n, const Vec3& on) const {
    const Vec3 corner((n.x() > 0 ? hi : lo).x(), (n.y() > 0 ? hi : lo).y(), (n.z() > 0 ? hi : lo).z());
    const double plane = n.dot(on) + tolerance;
    if (n.dot(corner) <= plane) return true;
    return std::none_of(vertices.begin(), vertices.end(), [&](const Vec3& v) { return n.dot(v) > plane; });
  }
};

}  // namespace

std::vector<std::uint8_t> openSides(const Scene& scene) {
  std::vector<std::uint8_t> open(scene.faces().size(), 0);
  if (scene.faces().empty()) return open;
  const SceneExtent extent(scene);
  const auto faces = static_cast<std::int64_t>(open.size());
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 256)
#endif
  for (std::int64_t k = 0; k < faces; ++k) {
    const Face& f = scene.faces()[static_cast<size_t>(k)];
    open[static_cast<size_t>(k)] = static_cast<std::uint8_t>((extent.behind(f.normal, f.v[0]) ? kFrontOpen : 0) |
                                        (extent.behind(-f.normal, f.v[0]) ? kBackOpen : 0));
  }
  return open;
}

bool nodeOpen(const Node& node, const std::vector<std::uint8_t>& open_sides) {
  const std::uint8_t bit = node.side > 0 ? kFrontOpen : kBackOpen;
  return std::all_of(node.faces.begin(), node.faces.end(),
                     [&](int f) { return (open_sides[static_cast<size_t>(f)] & bit) != 0; });
}

}  // namespace radnet::geometry
