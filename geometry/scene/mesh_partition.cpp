#include "geometry/scene/mesh_partition.hpp"

#include "solver/units.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

namespace radnet::geometry {
namespace {

// Union–find with path halving.
struct Sets {
  std::vector<int> parent;
  explicit Sets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[static_cast<size_t>(a)] != a)
      a = parent[static_cast<size_t>(a)] = parent[static_cast<size_t>(parent[static_cast<size_t>(a)])];
    return a;
  }
  void join(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
  }
};

Vec3 unitNormal(const TriangleSoup& s, const std::array<int, 3>& t) {
  const Vec3 &a = s.vertices[static_cast<size_t>(t[0])], &b = s.vertices[static_cast<size_t>(t[1])],
             &c = s.vertices[static_cast<size_t>(t[2])];
  return (b - a).cross(c - a).normalized();
}

// Triangles joined across smooth edges (two triangles, normals within the angle; an edge
// wound against its neighbour compares the one normal with the other's reverse).
Sets smoothRegions(const TriangleSoup& soup, double feature_angle_deg) {
  const double min_cos = std::cos(units::degToRad(feature_angle_deg));
  std::map<std::pair<int, int>, std::vector<std::pair<int, bool>>> edges;  // → (triangle, runs lo→hi)
  for (size_t t = 0; t < soup.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const int u = soup.triangles[t][static_cast<size_t>(k)], v = soup.triangles[t][static_cast<size_t>((k + 1) % 3)];
      edges[{std::min(u, v), std::max(u, v)}].push_back({static_cast<int>(t), u < v});
    }
  Sets sets(soup.triangles.size());
  for (const auto& [e, on] : edges) {
    if (on.size() != 2) continue;  // an open edge, or one of three or more triangles: a border
    const Vec3 n0 = unitNormal(soup, soup.triangles[static_cast<size_t>(on[0].first)]);
    Vec3 n1 = unitNormal(soup, soup.triangles[static_cast<size_t>(on[1].first)]);
    if (on[0].second == on[1].second) n1 = -n1;
    if (n0.dot(n1) >= min_cos) sets.join(on[0].first, on[1].first);
  }
  return sets;
}

// The triangles of each label as soups keeping only the vertices they use, in the order of
// each label's first triangle.
std::vector<MeshGroup> gather(const TriangleSoup& soup, const std::vector<int>& label, bool name_by_label) {
  std::vector<int> order;
  std::map<int, size_t> part_of;
  for (int l : label)
    if (part_of.emplace(l, order.size()).second) order.push_back(l);
  std::vector<MeshGroup> parts(order.size());
  std::vector<std::vector<int>> remap(order.size());
  for (size_t p = 0; p < order.size(); ++p) {
    parts[p].name = std::to_string(name_by_label ? order[p] : static_cast<int>(p));
    remap[p].assign(soup.vertices.size(), -1);
  }
  const bool has_nominal = soup.nominal.size() == soup.vertices.size();
  for (size_t t = 0; t < soup.triangles.size(); ++t) {
    const size_t p = part_of.at(label[t]);
    TriangleSoup& out = parts[p].soup;
    std::array<int, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const int v = soup.triangles[t][static_cast<size_t>(k)];
      int& r = remap[p][static_cast<size_t>(v)];
      if (r < 0) {
        r = static_cast<int>(out.vertices.size());
        out.vertices.push_back(soup.vertices[static_cast<size_t>(v)]);
        if (has_nominal) out.nominal.push_back(soup.nominal[static_cast<size_t>(v)]);
        if (soup.normals.size() == soup.vertices.size()) out.normals.push_back(soup.normals[static_cast<size_t>(v)]);
      }
      tri[static_cast<size_t>(k)] = r;
    }
    out.triangles.push_back(tri);
    if (soup.element.size() == soup.triangles.size()) out.element.push_back(soup.element[t]);
  }
  return parts;
}

}  // namespace

std::vector<MeshGroup> splitMesh(const TriangleSoup& soup, MeshNodes how, double feature_angle_deg) {
  if (how == MeshNodes::Single || how == MeshNodes::Groups) return {MeshGroup{"", soup}};
  std::vector<int> label(soup.triangles.size());
  if (how == MeshNodes::Elements) {
    for (size_t t = 0; t < label.size(); ++t)
      label[t] = soup.element.size() == soup.triangles.size() ? soup.element[t] : static_cast<int>(t);
    return gather(soup, label, true);
  }
  if (how == MeshNodes::Components) {
    Sets vertices(soup.vertices.size());
    for (const auto& t : soup.triangles) {
      vertices.join(t[0], t[1]);
      vertices.join(t[0], t[2]);
    }
    for (size_t t = 0; t < label.size(); ++t) label[t] = vertices.find(soup.triangles[t][0]);
  } else {
    Sets regions = smoothRegions(soup, feature_angle_deg);
    for (size_t t = 0; t < label.size(); ++t) label[t] = regions.find(static_cast<int>(t));
  }
  return gather(soup, label, false);
}

}  // namespace radnet::geometry
