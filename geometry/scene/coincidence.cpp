#include "geometry/scene/coincidence.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

namespace radnet::geometry {
namespace {

using Vec2 = Eigen::Vector2d;

// A face in the frame its plane group shares: the face's own unit normal (sign chosen with a
// positive leading component, so that opposite windings meet in one group), its corners in
// the group's 2-D frame, and the active sides' directions along that normal.
struct Planar {
  int face;
  Vec3 normal;
  std::array<Vec2, 3> corner;
  double x_min, x_max, y_min, y_max;
  bool up, down;  // an active side faces +normal / −normal
};

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double area(const std::vector<Vec2>& poly) {
  double a = 0.0;
  for (size_t k = 0; k < poly.size(); ++k) a += cross(poly[k], poly[(k + 1) % poly.size()]);
  return 0.5 * std::abs(a);
}

// Area of the intersection of two triangles: Sutherland–Hodgman, clipping `subject` by each
// edge of the counter-clockwise `clip`.
double overlapArea(std::array<Vec2, 3> subject, std::array<Vec2, 3> clip) {
  const auto ccw = [](std::array<Vec2, 3>& t) {
    if (cross(t[1] - t[0], t[2] - t[0]) < 0) std::swap(t[1], t[2]);
  };
  ccw(subject);
  ccw(clip);
  std::vector<Vec2> poly(subject.begin(), subject.end());
  for (int e = 0; e < 3 && !poly.empty(); ++e) {
    const Vec2 a = clip[e], b = clip[(e + 1) % 3];
    const auto inside = [&](const Vec2& p) { return cross(b - a, p - a) >= 0; };
    std::vector<Vec2> out;
    for (size_t k = 0; k < poly.size(); ++k) {
      const Vec2 p = poly[k], q = poly[(k + 1) % poly.size()];
      const bool pin = inside(p), qin = inside(q);
      if (pin) out.push_back(p);
      if (pin != qin) {
        const double t = cross(b - a, a - p) / cross(b - a, q - p);
        out.push_back(p + t * (q - p));
      }
    }
    poly.swap(out);
  }
  return poly.size() < 3 ? 0.0 : area(poly);
}

// The face's unit normal with a positive leading component, and the sign that took it there.
Vec3 canonicalNormal(const Face& f, double& sign) {
  sign = 1.0;
  for (int k = 0; k < 3; ++k)
    if (std::abs(f.normal[k]) > 1e-12) {
      sign = f.normal[k] < 0 ? -1.0 : 1.0;
      break;
    }
  return sign * f.normal;
}

// Face `index` projected into the frame (u, v) its plane group shares. One frame per group:
// with a frame per face, two neighbours a round-off apart in normal projected their shared
// edge to two different lines and showed a sliver of overlap that was not there (1e-7 m on
// a 20,000-triangle body exported off-origin).
Planar planar(const Scene& scene, int index, const Vec3& u, const Vec3& v) {
  const Face& f = scene.faces()[static_cast<size_t>(index)];
  double sign = 1.0;
  const Vec3 n = canonicalNormal(f, sign);
  Planar p{index, n, {}, INFINITY, -INFINITY, INFINITY, -INFINITY, false, false};
  for (int k = 0; k < 3; ++k) {
    p.corner[k] = Vec2(u.dot(f.v[k]), v.dot(f.v[k]));
    p.x_min = std::min(p.x_min, p.corner[k].x()), p.x_max = std::max(p.x_max, p.corner[k].x());
    p.y_min = std::min(p.y_min, p.corner[k].y()), p.y_max = std::max(p.y_max, p.corner[k].y());
  }
  // The front side faces along f.normal = sign · n.
  p.up = (f.front_node >= 0 && sign > 0) || (f.back_node >= 0 && sign < 0);
  p.down = (f.front_node >= 0 && sign < 0) || (f.back_node >= 0 && sign > 0);
  return p;
}

// Both faces lie in one plane: every corner of each within `tol` of the other's plane,
// measured from the other's own corner (never from the origin, which may be far away).
bool coplanar(const Scene& scene, const Planar& p, const Planar& q, double tol) {
  const Face& a = scene.faces()[static_cast<size_t>(p.face)];
  const Face& b = scene.faces()[static_cast<size_t>(q.face)];
  for (int k = 0; k < 3; ++k)
    if (std::abs(p.normal.dot(b.v[k] - a.v[0])) > tol || std::abs(q.normal.dot(a.v[k] - b.v[0])) > tol) return false;
  return true;
}

double perimeter(const std::array<Vec2, 3>& c) {
  return (c[1] - c[0]).norm() + (c[2] - c[1]).norm() + (c[0] - c[2]).norm();
}

using PlaneKey = std::tuple<long long, long long, long long, long long>;

}  // namespace

std::vector<Coincidence> coincidentFaces(const Scene& scene, size_t max_pairs) {
  const double tol = kCoincidencePlaneTolerance * std::max(scene.extent(), 1e-300);
  // Faces by plane: the normal to 1e-6 and the offset to 4 tol, each plane group then swept
  // along its first in-plane coordinate. A plane whose offset straddles two bins is found
  // from both (a bin is joined with the next one of the same normal).
  std::map<PlaneKey, std::vector<int>> planes;
  for (int i = 0; i < static_cast<int>(scene.faces().size()); ++i) {
    const Face& f = scene.faces()[static_cast<size_t>(i)];
    if (f.front_node < 0 && f.back_node < 0) continue;  // an occluder absorbs nothing
    double sign = 1.0;
    const Vec3 n = canonicalNormal(f, sign);
    const Vec3 centroid = (f.v[0] + f.v[1] + f.v[2]) / 3.0;
    planes[{std::llround(n.x() * 1e6), std::llround(n.y() * 1e6), std::llround(n.z() * 1e6),
            static_cast<long long>(std::floor(n.dot(centroid) / (4 * tol)))}]
        .push_back(i);
  }
  std::vector<Coincidence> found;
  std::set<std::pair<int, int>> seen;  // a pair near a bin edge is met from both bins
  for (auto it = planes.begin(); it != planes.end() && found.size() < max_pairs; ++it) {
    std::vector<int> members = it->second;
    auto next = std::next(it);  // the neighbouring offset bin of the same normal
    const PlaneKey& k = it->first;
    if (next != planes.end() && std::get<0>(next->first) == std::get<0>(k) &&
        std::get<1>(next->first) == std::get<1>(k) && std::get<2>(next->first) == std::get<2>(k) &&
        std::get<3>(next->first) == std::get<3>(k) + 1)
      members.insert(members.end(), next->second.begin(), next->second.end());
    if (members.size() < 2) continue;
    double sign = 1.0;
    const Vec3 n = canonicalNormal(scene.faces()[static_cast<size_t>(members.front())], sign);
    const Vec3 u = (std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(n).normalized(), v = n.cross(u);
    std::vector<Planar> faces;
    for (int m : members) faces.push_back(planar(scene, m, u, v));
    std::sort(faces.begin(), faces.end(), [](const Planar& a, const Planar& b) { return a.x_min < b.x_min; });
    for (size_t a = 0; a < faces.size() && found.size() < max_pairs; ++a)
      for (size_t b = a + 1; b < faces.size() && faces[b].x_min < faces[a].x_max; ++b) {
        const Planar &p = faces[a], &q = faces[b];
        if (q.y_min >= p.y_max || p.y_min >= q.y_max) continue;
        if (!((p.up && q.up) || (p.down && q.down))) continue;
        if (!coplanar(scene, p, q, tol)) continue;
        const double overlap = overlapArea(p.corner, q.corner);
        const double smaller = std::min(scene.faces()[static_cast<size_t>(p.face)].area_m2,
                                        scene.faces()[static_cast<size_t>(q.face)].area_m2);
        // Round-off can open a strip `tol` wide along the edges two neighbours share (or along
        // a vertex that lies on a neighbour's edge): only an overlap above that is one.
        const double round_off = tol * std::max(perimeter(p.corner), perimeter(q.corner));
        const std::pair<int, int> pair{std::min(p.face, q.face), std::max(p.face, q.face)};
        if (overlap > std::max(kCoincidenceMinShare * smaller, round_off) && seen.insert(pair).second)
          found.push_back({pair.first, pair.second, overlap});
        if (found.size() >= max_pairs) break;
      }
  }
  return found;
}

}  // namespace radnet::geometry
