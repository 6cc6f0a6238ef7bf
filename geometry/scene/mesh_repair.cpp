#include "geometry/scene/mesh_repair.hpp"

#include "geometry/scene/vertex_welder.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

namespace radnet::geometry {
namespace {

// Undirected edge (smaller vertex first) → triangles running along it lo→hi and hi→lo.
struct EdgeUse {
  int forward = 0, backward = 0;
  int first_triangle = -1;  // the file's number of the first triangle on it
};
using EdgeMap = std::map<std::pair<int, int>, EdgeUse>;

void checkIndices(const TriangleSoup& soup) {
  for (size_t i = 0; i < soup.vertices.size(); ++i)
    if (!soup.vertices[i].allFinite()) {
      std::ostringstream s;
      s << "vertex " << i << " has a non-finite coordinate";
      throw GeometryError(s.str());
    }
  for (size_t t = 0; t < soup.triangles.size(); ++t)
    for (int idx : soup.triangles[t])
      if (idx < 0 || idx >= static_cast<int>(soup.vertices.size())) {
        std::ostringstream s;
        s << "triangle " << t << " refers to vertex " << idx << " of " << soup.vertices.size();
        throw GeometryError(s.str());
      }
}

// The triangle's corners rotated so the smallest comes first (the winding kept): two
// triangles with the same key are the same triangle, wound the same way.
std::array<int, 3> rotatedKey(const std::array<int, 3>& t) {
  const int k = static_cast<int>(std::min_element(t.begin(), t.end()) - t.begin());
  return {t[static_cast<size_t>(k)], t[static_cast<size_t>((k + 1) % 3)], t[static_cast<size_t>((k + 2) % 3)]};
}

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// The loops of the open edges, each edge run in its triangle's direction.
std::vector<std::vector<std::pair<int, int>>> openLoops(const EdgeMap& edges) {
  std::multimap<int, int> next;  // open edge: start → end
  for (const auto& [e, use] : edges)
    if (use.forward + use.backward == 1) {
      if (use.forward) next.emplace(e.first, e.second);
      else next.emplace(e.second, e.first);
    }
  std::vector<std::vector<std::pair<int, int>>> loops;
  while (!next.empty()) {
    const int start = next.begin()->first;
    int at = start;
    loops.emplace_back();
    for (auto it = next.find(at); it != next.end(); it = next.find(at)) {
      loops.back().push_back({at, it->second});
      at = it->second;
      next.erase(it);
      if (at == start) break;
    }
  }
  return loops;
}

// The area of the holes the open edges leave. A loop's hole is the smaller of the area it
// bounds, |½ Σ (p_i − p_0) × (p_{i+1} − p_0)| (a missing triangle), and its length times the
// distance across to the nearest other loop (a crack: its two sides are two loops, each
// bounding a whole face). The second is O(m²) in the m open edges, so beyond
// kMaxCrackEdges only the first is taken (an overestimate: the mesh is then called open).
double holeArea(const EdgeMap& edges, const std::vector<Vec3>& p) {
  constexpr size_t kMaxCrackEdges = 4000;
  const auto loops = openLoops(edges);
  size_t open = 0;
  for (const auto& l : loops) open += l.size();
  const auto at = [&](int v) -> const Vec3& { return p[static_cast<size_t>(v)]; };
  double total = 0.0;
  for (size_t a = 0; a < loops.size(); ++a) {
    Vec3 twice = Vec3::Zero();
    const Vec3& origin = at(loops[a].front().first);
    for (const auto& [u, v] : loops[a]) twice += (at(u) - origin).cross(at(v) - origin);
    double hole = 0.5 * twice.norm();
    if (open <= kMaxCrackEdges && loops.size() > 1) {
      double across = 0.0;
      for (const auto& [u, v] : loops[a]) {
        const Vec3 mid = 0.5 * (at(u) + at(v));
        double nearest = std::numeric_limits<double>::infinity();
        for (size_t b = 0; b < loops.size(); ++b)
          if (b != a)
            for (const auto& [x, y] : loops[b]) nearest = std::min(nearest, distanceToSegment(mid, at(x), at(y)));
        across += (at(v) - at(u)).norm() * nearest;
      }
      hole = std::min(hole, across);
    }
    total += hole;
  }
  return total;
}

// Two file normals of a welded vertex closer than this (unit vectors, ~0.06°) are one.
constexpr double kSameNormal = 1e-3;

// Welds the vertices (the first seen of each cluster stands for it), keeping only those the
// triangles use; returns each old vertex's new index.
std::vector<int> weldVertices(TriangleSoup& soup, double tolerance, MeshReport& r) {
  VertexWelder welder(tolerance);
  std::vector<int> cluster(soup.vertices.size());
  for (size_t v = 0; v < soup.vertices.size(); ++v) cluster[v] = welder.id(soup.vertices[v]);
  std::vector<char> used(soup.vertices.size(), 0);
  for (const auto& t : soup.triangles)
    for (int v : t) used[static_cast<size_t>(v)] = 1;
  std::vector<int> renumber(soup.vertices.size(), -1), new_index(soup.vertices.size(), -1);
  std::vector<Vec3> vertices, nominal, normals;
  const bool has_nominal = soup.nominal.size() == soup.vertices.size();
  const bool has_normals = soup.normals.size() == soup.vertices.size();
  for (size_t v = 0; v < soup.vertices.size(); ++v) {
    if (!used[v]) continue;
    int& slot = renumber[static_cast<size_t>(cluster[v])];
    if (slot < 0) {
      slot = static_cast<int>(vertices.size());
      vertices.push_back(welder.point(cluster[v]));
      if (has_nominal) nominal.push_back(soup.nominal[v]);
      if (has_normals) normals.push_back(soup.normals[v]);
    } else if (has_normals && !(normals[static_cast<size_t>(slot)] - soup.normals[v]).isZero(kSameNormal)) {
      normals[static_cast<size_t>(slot)].setZero();  // welded across a hard edge: facet normals there
    }
    if (soup.vertices[v] != welder.point(cluster[v])) ++r.welded_vertices;
    new_index[v] = slot;
  }
  soup.vertices = std::move(vertices);
  soup.nominal = std::move(nominal);
  soup.normals = std::move(normals);
  return new_index;
}

// Drops degenerate and repeated triangles (the report numbers the file's faces).
void dropEmptyTriangles(TriangleSoup& soup, const std::vector<int>& new_index, double diagonal, MeshReport& r) {
  std::set<std::array<int, 3>> seen;
  std::vector<std::array<int, 3>> kept;
  std::vector<int> element;
  const bool has_element = soup.element.size() == soup.triangles.size();
  for (size_t t = 0; t < soup.triangles.size(); ++t) {
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) tri[static_cast<size_t>(k)] = new_index[static_cast<size_t>(soup.triangles[t][static_cast<size_t>(k)])];
    const Vec3 &a = soup.vertices[static_cast<size_t>(tri[0])], &b = soup.vertices[static_cast<size_t>(tri[1])],
               &c = soup.vertices[static_cast<size_t>(tri[2])];
    // The same bound as the scene's (geometry/scene/scene.cpp): below what double rounding resolves.
    const int face = has_element ? soup.element[t] : static_cast<int>(t);
    if (!((b - a).cross(c - a).norm() > 1e-12 * diagonal * diagonal)) {
      if (r.degenerate++ == 0) r.first_degenerate = face;
      continue;
    }
    if (!seen.insert(rotatedKey(tri)).second) {
      if (r.duplicate++ == 0) r.first_duplicate = face;
      continue;
    }
    kept.push_back(tri);
    element.push_back(face);
  }
  soup.triangles = std::move(kept);
  soup.element = std::move(element);
}

void measureEdges(const TriangleSoup& soup, MeshReport& r, EdgeMap& edges) {
  for (size_t t = 0; t < soup.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = soup.triangles[t][static_cast<size_t>(k)], v = soup.triangles[t][static_cast<size_t>((k + 1) % 3)];
      EdgeUse& use = edges[{std::min(u, v), std::max(u, v)}];
      (u < v ? use.forward : use.backward) += 1;
      if (use.first_triangle < 0) use.first_triangle = soup.element[t];
      r.shortest_edge_m =
          std::min(r.shortest_edge_m, (soup.vertices[static_cast<size_t>(u)] - soup.vertices[static_cast<size_t>(v)]).norm());
    }
  for (const auto& [e, use] : edges) {
    const int n = use.forward + use.backward;
    if (n == 1) {
      ++r.open_edges;
      r.open_length_m += (soup.vertices[static_cast<size_t>(e.first)] - soup.vertices[static_cast<size_t>(e.second)]).norm();
    } else if (n > 2) {
      ++r.non_manifold_edges;
    } else if (use.forward == 2 || use.backward == 2) {
      if (r.wound_against++ == 0) r.first_wound_against = use.first_triangle;
    }
  }
}

}  // namespace

MeshReport cleanMesh(TriangleSoup& soup, double weld_tolerance_m) {
  MeshReport r;
  checkIndices(soup);
  if (soup.vertices.empty() || soup.triangles.empty()) return r;
  Eigen::AlignedBox3d box;
  for (const Vec3& v : soup.vertices) box.extend(v);
  const double diagonal = box.diagonal().norm();
  r.extent_m = box.sizes().maxCoeff();
  const double weld = weld_tolerance_m > 0 ? weld_tolerance_m : kMeshWeldTolerance * std::max(diagonal, 1e-300);
  const std::vector<int> new_index = weldVertices(soup, weld, r);
  dropEmptyTriangles(soup, new_index, diagonal, r);
  if (soup.triangles.empty()) return r;
  EdgeMap edges;
  measureEdges(soup, r, edges);
  const Vec3 centre = box.center();  // the volume about the box's centre: least round-off
  for (const auto& t : soup.triangles) {
    const Vec3 a = soup.vertices[static_cast<size_t>(t[0])] - centre, b = soup.vertices[static_cast<size_t>(t[1])] - centre,
               c = soup.vertices[static_cast<size_t>(t[2])] - centre;
    r.area_m2 += 0.5 * (b - a).cross(c - a).norm();
    r.enclosed_volume_m3 += a.dot(b.cross(c)) / 6.0;
  }
  r.hole_area_m2 = holeArea(edges, soup.vertices);
  r.nearly_closed = r.hole_area_m2 <= kNearlyClosedHoleShare * r.area_m2;
  return r;
}

void transformMesh(TriangleSoup& soup, const Eigen::Matrix3d& rotation, const Vec3& translation) {
  for (Vec3& v : soup.vertices) v = rotation * v + translation;
  for (Vec3& v : soup.nominal) v = rotation * v + translation;
  for (Vec3& n : soup.normals) n = rotation * n;
}

void flipWinding(TriangleSoup& soup) {
  for (auto& t : soup.triangles) std::swap(t[1], t[2]);
}

}  // namespace radnet::geometry
