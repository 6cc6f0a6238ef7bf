#include "geometry/scene/facet_creases.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace radnet::geometry {

FacetCreases facetCreases(const Scene& scene, int node) {
  using Point = std::array<double, 3>;
  using Edge = std::pair<Point, Point>;
  const auto point = [](const Vec3& v) { return Point{v.x(), v.y(), v.z()}; };
  std::map<Edge, std::vector<int>> edges;  // an edge, its ends ordered, and the node's faces on it
  const Node& n = scene.nodes()[static_cast<size_t>(node)];
  for (int f : n.faces) {
    const Face& face = scene.faces()[static_cast<size_t>(f)];
    if (scene.hasSmoothNormal(f)) continue;
    for (int k = 0; k < 3; ++k) {
      Point a = point(face.v[static_cast<size_t>(k)]), b = point(face.v[static_cast<size_t>((k + 1) % 3)]);
      if (b < a) std::swap(a, b);
      edges[{a, b}].push_back(f);
    }
  }
  FacetCreases out;
  for (const auto& [edge, faces] : edges) {
    if (faces.size() != 2) continue;  // a boundary, or a non-manifold edge the mesh checks report
    const Vec3& n0 = scene.faces()[static_cast<size_t>(faces[0])].normal;
    const Vec3& n1 = scene.faces()[static_cast<size_t>(faces[1])].normal;
    // atan2 of |n0 × n1| and n0·n1: accurate at small angles, where acos is not.
    const double deg = std::atan2(n0.cross(n1).norm(), n0.dot(n1)) * 180.0 / M_PI;
    if (deg <= kFlatDeg || deg > kSharpEdgeDeg) continue;
    ++out.smooth_edges;
    out.largest_deg = std::max(out.largest_deg, deg);
    out.mean_deg += deg;
  }
  if (out.smooth_edges > 0) out.mean_deg /= out.smooth_edges;
  return out;
}

}  // namespace radnet::geometry
