// Rigid motion of whole surfaces: the articulated parts of a spacecraft (a Sun-tracking wing,
// a steered antenna) turned about their drive's axis.
#include "geometry/scene/scene.hpp"

#include <Eigen/Geometry>

#include <algorithm>

namespace radnet::geometry {

void Scene::rotateSurfaces(const std::vector<int>& surfaces, const Vec3& point, const Vec3& axis, double angle_rad) {
  if (surfaces.empty() || angle_rad == 0.0) return;
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  const auto moved = [&](const Vec3& p) -> Vec3 { return point + turn * (p - point); };
  std::vector<char> moving(surfaces_.size(), 0);
  for (int s : surfaces) moving.at(static_cast<size_t>(s)) = 1;
  for (Mesh::Vertex_index v : mesh_.vertices()) {
    const size_t k = static_cast<size_t>(v);
    if (!moving[static_cast<size_t>(vertex_surface_[k])]) continue;
    const Point3& p = mesh_.point(v);
    const Vec3 q = moved(Vec3(p.x(), p.y(), p.z()));
    mesh_.point(v) = Point3(q.x(), q.y(), q.z());
    nominal_[k] = moved(nominal_[k]);
  }
  for (size_t i = 0; i < faces_.size(); ++i) {
    Face& f = faces_[i];
    if (!moving[static_cast<size_t>(f.surface)]) continue;
    for (Vec3& v : f.v) v = moved(v);
    f.normal = turn * f.normal;
    if (!corner_normals_.empty())
      for (Vec3& n : corner_normals_[i]) n = turn * n;  // a zero (no file normal) stays zero
  }
  for (size_t s = 0; s < shapes_.size(); ++s)
    if (moving[s]) {
      shapes_[s].center = moved(shapes_[s].center);
      shapes_[s].axis = turn * shapes_[s].axis;
    }
}

}  // namespace radnet::geometry
