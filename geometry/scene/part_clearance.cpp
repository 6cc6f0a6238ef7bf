#include "geometry/scene/part_clearance.hpp"

#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <set>

namespace radnet::geometry {

std::vector<std::pair<int, int>> meetingSurfaces(const Scene& scene, const std::vector<int>& moving) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, int>;
  std::vector<char> turns(scene.surfaceNames().size(), 0);
  for (int s : moving) turns.at(static_cast<size_t>(s)) = 1;
  std::vector<Box> mover, rest;
  const std::vector<Face>& faces = scene.faces();
  for (size_t f = 0; f < faces.size(); ++f) {
    Eigen::Vector3d lo = faces[f].v[0], hi = lo;
    for (const Vec3& v : faces[f].v) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double pad = 1e-12 * std::max(1.0, (hi - lo).norm());  // flat boxes of axis-aligned triangles
    double l[3] = {lo.x() - pad, lo.y() - pad, lo.z() - pad}, h[3] = {hi.x() + pad, hi.y() + pad, hi.z() + pad};
    (turns[static_cast<size_t>(faces[f].surface)] ? mover : rest).emplace_back(l, h, static_cast<int>(f));
  }
  std::set<std::pair<int, int>> met;
  const auto triangle = [&](int f) {
    const auto& v = faces[static_cast<size_t>(f)].v;
    return Kernel::Triangle_3(Point3(v[0].x(), v[0].y(), v[0].z()), Point3(v[1].x(), v[1].y(), v[1].z()),
                              Point3(v[2].x(), v[2].y(), v[2].z()));
  };
  CGAL::box_intersection_d(mover.begin(), mover.end(), rest.begin(), rest.end(), [&](const Box& a, const Box& b) {
    const int sa = faces[static_cast<size_t>(a.info())].surface, sb = faces[static_cast<size_t>(b.info())].surface;
    if (met.count({sa, sb})) return;
    if (CGAL::do_intersect(triangle(a.info()), triangle(b.info()))) met.insert({sa, sb});
  });
  return {met.begin(), met.end()};
}

}  // namespace radnet::geometry
