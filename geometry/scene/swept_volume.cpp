#include "geometry/scene/swept_volume.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::geometry {

double SweptCylinder::support(const Vec3& n) const {
  const double along = n.dot(axis);
  const double across = std::sqrt(std::max(0.0, 1.0 - along * along));
  return n.dot(point) + std::max(along * axial_min, along * axial_max) + radius * across;
}

bool SweptCylinder::meets(const Vec3& origin, const Vec3& dir) const {
  // Along the axis the half-line is in the slab for t in [t0, t1]; across it, within the
  // radius for t in [s0, s1] (a quadratic in t); it meets the solid where both overlap.
  const Vec3 o = origin - point;
  const double oa = o.dot(axis), da = dir.dot(axis);
  double lo = 0.0, hi = INFINITY;
  if (std::abs(da) < 1e-300) {
    if (oa < axial_min || oa > axial_max) return false;
  } else {
    double t0 = (axial_min - oa) / da, t1 = (axial_max - oa) / da;
    if (t0 > t1) std::swap(t0, t1);
    lo = std::max(lo, t0);
    hi = std::min(hi, t1);
  }
  const Vec3 op = o - oa * axis, dp = dir - da * axis;  // across the axis
  const double a = dp.squaredNorm(), b = op.dot(dp), c = op.squaredNorm() - radius * radius;
  if (a < 1e-300) {
    if (c > 0) return false;
  } else {
    const double disc = b * b - a * c;
    if (disc < 0) return false;
    const double root = std::sqrt(disc);
    lo = std::max(lo, (-b - root) / a);
    hi = std::min(hi, (-b + root) / a);
  }
  return lo <= hi;
}

SweptCylinder sweptCylinder(const Scene& scene, const std::vector<int>& surfaces, const Vec3& point, const Vec3& axis) {
  SweptCylinder c;
  c.point = point;
  c.axis = axis.normalized();
  c.axial_min = INFINITY;
  c.axial_max = -INFINITY;
  std::vector<char> moving(scene.surfaceNames().size(), 0);
  for (int s : surfaces) moving.at(static_cast<size_t>(s)) = 1;
  for (const Face& f : scene.faces()) {
    if (!moving[static_cast<size_t>(f.surface)]) continue;
    for (const Vec3& v : f.v) {
      const Vec3 d = v - point;
      const double t = d.dot(c.axis);
      c.axial_min = std::min(c.axial_min, t);
      c.axial_max = std::max(c.axial_max, t);
      c.radius = std::max(c.radius, (d - t * c.axis).norm());
    }
  }
  if (!(c.axial_min <= c.axial_max)) c.axial_min = c.axial_max = 0.0;  // no triangle: a point
  return c;
}

std::vector<char> nodesFacing(const Scene& scene, const SweptCylinder& swept) {
  const double tolerance = 1e-9 * std::max(scene.extent(), 1e-300);
  std::vector<char> facing(scene.nodes().size(), 0);
  for (const Face& f : scene.faces()) {
    const double front = swept.support(f.normal) - f.normal.dot(f.v[0]);
    const double back = swept.support(-f.normal) + f.normal.dot(f.v[0]);
    if (f.front_node >= 0 && front > tolerance) facing[static_cast<size_t>(f.front_node)] = 1;
    if (f.back_node >= 0 && back > tolerance) facing[static_cast<size_t>(f.back_node)] = 1;
  }
  return facing;
}

}  // namespace radnet::geometry
