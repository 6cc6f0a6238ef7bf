#include "geometry/rays/ray_caster.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <algorithm>
#include <array>
#include <limits>
#include <utility>
#include <vector>

namespace radnet::geometry {

struct RayCaster::Tree {
  using Triangle = Kernel::Triangle_3;
  using Iterator = std::vector<Triangle>::const_iterator;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
  using Traits = CGAL::AABB_traits<Kernel, Primitive>;
  using AabbTree = CGAL::AABB_tree<Traits>;
  std::vector<Triangle> triangles;
  std::vector<int> face;  // the scene face each tree triangle is (a piece of)
  AabbTree tree;
};

namespace {

Point3 toPoint(const Vec3& v) { return Point3(v.x(), v.y(), v.z()); }

double longestEdge(const Face& f) {
  return std::max({(f.v[1] - f.v[0]).norm(), (f.v[2] - f.v[1]).norm(), (f.v[0] - f.v[2]).norm()});
}

// A triangle for the tree, split at the midpoint of its longest edge until no edge is longer
// than `target`: a long sliver's bounding box is large and overlaps thousands of others
// (CAD tessellations are full of them), and the tree's traversal, not the triangle tests,
// then takes the time. The pieces tile the triangle exactly (shared corners, one plane).
void addPieces(const std::array<Vec3, 3>& v, double target, int face, int depth, RayCaster::TreeInput& out) {
  int k = 0;
  double longest = 0.0;
  for (int e = 0; e < 3; ++e)
    if (const double l = (v[static_cast<size_t>((e + 1) % 3)] - v[static_cast<size_t>(e)]).norm(); l > longest)
      longest = l, k = e;
  if (longest <= target || depth == 0) {
    out.emplace_back(v, face);
    return;
  }
  const Vec3& a = v[static_cast<size_t>(k)];
  const Vec3& b = v[static_cast<size_t>((k + 1) % 3)];
  const Vec3& c = v[static_cast<size_t>((k + 2) % 3)];
  const Vec3 m = 0.5 * (a + b);
  addPieces({a, m, c}, target, face, depth - 1, out);
  addPieces({m, b, c}, target, face, depth - 1, out);
}

}  // namespace

RayCaster::RayCaster(const Scene& scene) : scene_(scene), tree_(std::make_unique<Tree>()) {
  // Pieces no longer than kSplitLength × the median longest edge (at most 2^kSplitDepth a face).
  std::vector<double> longest;
  for (const Face& f : scene.faces()) longest.push_back(longestEdge(f));
  double target = std::numeric_limits<double>::infinity();
  if (!longest.empty()) {
    std::vector<double> sorted = longest;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(sorted.size() / 2), sorted.end());
    target = kSplitLength * sorted[sorted.size() / 2];
  }
  TreeInput pieces;
  double max_coord = 0.0;
  for (size_t i = 0; i < scene.faces().size(); ++i) {
    const Face& f = scene.faces()[i];
    addPieces(f.v, target, static_cast<int>(i), kSplitDepth, pieces);
    for (const auto& v : f.v) max_coord = std::max(max_coord, v.cwiseAbs().maxCoeff());
  }
  tree_->triangles.reserve(pieces.size());
  for (const auto& [v, face] : pieces) {
    tree_->triangles.emplace_back(toPoint(v[0]), toPoint(v[1]), toPoint(v[2]));
    tree_->face.push_back(face);
  }
  tree_->tree.insert(tree_->triangles.cbegin(), tree_->triangles.cend());
  tree_->tree.build();  // before any parallel query: CGAL builds lazily otherwise
  // A point interpolated on a triangle carries a rounding error of a few ulps of the
  // largest coordinate; 64 ulps leaves a safe margin and stays far below any feature size.
  offset_scale_ = 64.0 * std::numeric_limits<double>::epsilon() * std::max(max_coord, 1e-300);
}

RayCaster::~RayCaster() = default;

Vec3 RayCaster::offsetOrigin(const Vec3& point, const Vec3& side_normal) const {
  return point + offset_scale_ * side_normal;
}

Hit RayCaster::firstHit(const Vec3& origin, const Vec3& dir, int skip) const {
  const Kernel::Ray_3 ray(toPoint(origin), Kernel::Vector_3(dir.x(), dir.y(), dir.z()));
  const auto begin = tree_->triangles.cbegin();
  const std::vector<int>& face = tree_->face;
  auto hit = tree_->tree.first_intersection(
      ray, [&](const Tree::Iterator& it) { return face[static_cast<size_t>(it - begin)] == skip; });
  Hit out;
  if (!hit) return out;
  out.face = face[static_cast<size_t>(hit->second - begin)];
  const Face& f = scene_.faces()[static_cast<size_t>(out.face)];
  out.front = f.normal.dot(dir) < 0.0;
  if (const Point3* p = boost::get<Point3>(&hit->first)) {
    out.distance = (Vec3(p->x(), p->y(), p->z()) - origin).norm();
  }
  return out;
}

}  // namespace radnet::geometry
