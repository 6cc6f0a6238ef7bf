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

// Cell index of x on a grid from `origin` of cells `width` wide (clamped: a far outlier
// lands in the last cell, where the boxes' own test still tells it apart).
long cellOf(double x, double origin, double width, long cells) {
  return std::clamp(static_cast<long>(std::floor((x - origin) / width)), 0L, cells - 1);
}

// Calls fn(p, q) once for every two faces of one plane whose boxes overlap, until fn returns
// false. A grid of cells as wide as the median box along each axis (doubled while the faces
// would enter more than 8 cells each on average, or the cells outnumber the faces 4 to 1): a
// face enters every cell its box reaches, and a pair is tested only in the cell that holds
// the lower corner of its boxes' overlap. A sweep along one axis tested every two faces of a
// long row: 7e10 pairs, a minute, on a plate cut 10,000 × 180 (a fuzzed case file).
template <class Fn>
void forOverlappingBoxes(const std::vector<Planar>& faces, Fn&& fn) {
  const size_t m = faces.size();
  double x0 = INFINITY, y0 = INFINITY, x1 = -INFINITY, y1 = -INFINITY;
  std::vector<double> wx, wy;
  for (const Planar& f : faces) {
    x0 = std::min(x0, f.x_min), x1 = std::max(x1, f.x_max), y0 = std::min(y0, f.y_min), y1 = std::max(y1, f.y_max);
    wx.push_back(f.x_max - f.x_min), wy.push_back(f.y_max - f.y_min);
  }
  std::nth_element(wx.begin(), wx.begin() + static_cast<std::ptrdiff_t>(m / 2), wx.end());
  std::nth_element(wy.begin(), wy.begin() + static_cast<std::ptrdiff_t>(m / 2), wy.end());
  const double floor_width = std::max(1e-9 * std::max(x1 - x0, y1 - y0), 1e-300);
  double cx = std::max(wx[m / 2], floor_width), cy = std::max(wy[m / 2], floor_width);
  long nx = 1, ny = 1;
  for (;;) {
    nx = static_cast<long>(std::min((x1 - x0) / cx, 1e9)) + 1, ny = static_cast<long>(std::min((y1 - y0) / cy, 1e9)) + 1;
    double entries = 0.0;
    for (const Planar& f : faces)
      entries += double(cellOf(f.x_max, x0, cx, nx) - cellOf(f.x_min, x0, cx, nx) + 1) *
                 double(cellOf(f.y_max, y0, cy, ny) - cellOf(f.y_min, y0, cy, ny) + 1);
    if ((entries <= 8.0 * double(m) && double(nx) * double(ny) <= 4.0 * double(m) + 16) || (nx == 1 && ny == 1)) break;
    cx *= 2, cy *= 2;
  }
  // The faces of each cell, by a counting sort over the cells (in face order within one).
  std::vector<long> start(static_cast<size_t>(nx * ny) + 1, 0);
  const auto span = [&](const Planar& f, auto&& visit) {
    for (long j = cellOf(f.y_min, y0, cy, ny); j <= cellOf(f.y_max, y0, cy, ny); ++j)
      for (long i = cellOf(f.x_min, x0, cx, nx); i <= cellOf(f.x_max, x0, cx, nx); ++i) visit(j * nx + i);
  };
  for (const Planar& f : faces) span(f, [&](long c) { ++start[static_cast<size_t>(c) + 1]; });
  for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
  std::vector<int> members(static_cast<size_t>(start.back()));
  std::vector<long> fill(start.begin(), start.end() - 1);
  for (size_t k = 0; k < m; ++k) span(faces[k], [&](long c) { members[static_cast<size_t>(fill[static_cast<size_t>(c)]++)] = static_cast<int>(k); });
  for (long c = 0; c < nx * ny; ++c)
    for (long a = start[static_cast<size_t>(c)]; a < start[static_cast<size_t>(c) + 1]; ++a)
      for (long b = a + 1; b < start[static_cast<size_t>(c) + 1]; ++b) {
        const Planar &p = faces[static_cast<size_t>(members[static_cast<size_t>(a)])];
        const Planar &q = faces[static_cast<size_t>(members[static_cast<size_t>(b)])];
        if (q.x_min >= p.x_max || p.x_min >= q.x_max || q.y_min >= p.y_max || p.y_min >= q.y_max) continue;
        const long corner = cellOf(std::max(p.y_min, q.y_min), y0, cy, ny) * nx + cellOf(std::max(p.x_min, q.x_min), x0, cx, nx);
        if (corner == c && !fn(p, q)) return;
      }
}

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
    forOverlappingBoxes(faces, [&](const Planar& p, const Planar& q) {
      if (!((p.up && q.up) || (p.down && q.down))) return true;
      if (!coplanar(scene, p, q, tol)) return true;
      const double overlap = overlapArea(p.corner, q.corner);
      const double smaller = std::min(scene.faces()[static_cast<size_t>(p.face)].area_m2,
                                      scene.faces()[static_cast<size_t>(q.face)].area_m2);
      // Round-off can open a strip `tol` wide along the edges two neighbours share (or along
      // a vertex that lies on a neighbour's edge): only an overlap above that is one.
      const double round_off = tol * std::max(perimeter(p.corner), perimeter(q.corner));
      const std::pair<int, int> pair{std::min(p.face, q.face), std::max(p.face, q.face)};
      if (overlap > std::max(kCoincidenceMinShare * smaller, round_off) && seen.insert(pair).second)
        found.push_back({pair.first, pair.second, overlap});
      return found.size() < max_pairs;
    });
  }
  return found;
}

}  // namespace radnet::geometry
