#include "geometry/rays/ray_caster.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <limits>

namespace radnet::geometry {

struct RayCaster::Tree {
  using Triangle = Kernel::Triangle_3;
  using Iterator = std::vector<Triangle>::const_iterator;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, Iterator>;
  using Traits = CGAL::AABB_traits<Kernel, Primitive>;
  using AabbTree = CGAL::AABB_tree<Traits>;
  std::vector<Triangle> triangles;
  AabbTree tree;
};

namespace {
Point3 toPoint(const Vec3& v) { return Point3(v.x(), v.y(), v.z()); }
}  // namespace

RayCaster::RayCaster(const Scene& scene) : scene_(scene), tree_(std::make_unique<Tree>()) {
  tree_->triangles.reserve(scene.faces().size());
  double max_coord = 0.0;
  for (const Face& f : scene.faces()) {
    tree_->triangles.emplace_back(toPoint(f.v[0]), toPoint(f.v[1]), toPoint(f.v[2]));
    for (const auto& v : f.v) max_coord = std::max(max_coord, v.cwiseAbs().maxCoeff());
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
  auto hit = tree_->tree.first_intersection(
      ray, [&](const Tree::Iterator& it) { return static_cast<int>(it - begin) == skip; });
  Hit out;
  if (!hit) return out;
  out.face = static_cast<int>(hit->second - begin);
  const Face& f = scene_.faces()[static_cast<size_t>(out.face)];
  out.front = f.normal.dot(dir) < 0.0;
  if (const Point3* p = boost::get<Point3>(&hit->first)) {
    out.distance = (Vec3(p->x(), p->y(), p->z()) - origin).norm();
  }
  return out;
}

}  // namespace radnet::geometry
