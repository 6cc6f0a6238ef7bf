#include "geometry/scene/shell.hpp"

#include "geometry/scene/vertex_welder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace radnet::geometry {
namespace {

struct SharedEdges {
  double length = 0.0;
  Vec3 weighted_midpoint = Vec3::Zero();  // Σ L m
};

// Edges shared by triangles of different nodes on the same side, by node pair.
std::map<std::pair<int, int>, SharedEdges> sharedEdges(const std::vector<Face>& faces,
                                                       const std::map<std::pair<int, int>, std::vector<int>>& edge_faces,
                                                       VertexWelder& welder) {
  std::map<std::pair<int, int>, SharedEdges> shared;
  for (const auto& [edge, list] : edge_faces) {
    if (list.size() < 2) continue;
    const Face& f0 = faces[static_cast<size_t>(list[0])];
    // The edge's end points, from the first face that has it.
    Vec3 p, q;
    for (int k = 0; k < 3; ++k) {
      const Vec3 &a = f0.v[static_cast<size_t>(k)], &b = f0.v[static_cast<size_t>((k + 1) % 3)];
      if (welder.id(a) == edge.first && welder.id(b) == edge.second) p = a, q = b;
      if (welder.id(b) == edge.first && welder.id(a) == edge.second) p = b, q = a;
    }
    const double length = (q - p).norm();
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j) {
        const Face &fi = faces[static_cast<size_t>(list[i])], &fj = faces[static_cast<size_t>(list[j])];
        for (const auto& [a, b] : {std::pair{fi.front_node, fj.front_node}, std::pair{fi.back_node, fj.back_node}}) {
          if (a < 0 || b < 0 || a == b) continue;
          SharedEdges& s = shared[{std::min(a, b), std::max(a, b)}];
          s.length += length;
          s.weighted_midpoint += length * 0.5 * (p + q);
        }
      }
  }
  return shared;
}

}  // namespace

ShellAdjacency shellAdjacency(const Scene& scene, int first_face, int end_face) {
  const std::vector<Face>& faces = scene.faces();
  Eigen::AlignedBox3d box;
  for (int f = first_face; f < end_face; ++f)
    for (const Vec3& v : faces[static_cast<size_t>(f)].v) box.extend(v);
  VertexWelder welder(1e-9 * std::max(box.diagonal().norm(), 1e-300));
  std::map<std::pair<int, int>, std::vector<int>> edge_faces;
  std::map<int, std::pair<double, Vec3>> centroid;  // node → (area, Σ A c)
  std::map<std::pair<int, int>, double> front_back;
  for (int f = first_face; f < end_face; ++f) {
    const Face& face = faces[static_cast<size_t>(f)];
    std::array<int, 3> id;
    for (int k = 0; k < 3; ++k) id[static_cast<size_t>(k)] = welder.id(face.v[static_cast<size_t>(k)]);
    for (int k = 0; k < 3; ++k) {
      const int a = id[static_cast<size_t>(k)], b = id[static_cast<size_t>((k + 1) % 3)];
      edge_faces[{std::min(a, b), std::max(a, b)}].push_back(f);
    }
    const Vec3 c = (face.v[0] + face.v[1] + face.v[2]) / 3.0;
    for (int node : {face.front_node, face.back_node}) {
      if (node < 0) continue;
      auto& [area, weighted] = centroid.try_emplace(node, 0.0, Vec3::Zero()).first->second;
      area += face.area_m2;
      weighted += face.area_m2 * c;
    }
    if (face.front_node >= 0 && face.back_node >= 0) front_back[{face.front_node, face.back_node}] += face.area_m2;
  }
  const std::map<std::pair<int, int>, SharedEdges> shared = sharedEdges(faces, edge_faces, welder);
  ShellAdjacency out;
  for (const auto& [pair, s] : shared) {
    const Vec3 m = s.weighted_midpoint / s.length;
    const auto& [area_a, sum_a] = centroid.at(pair.first);
    const auto& [area_b, sum_b] = centroid.at(pair.second);
    const double d_a = (sum_a / area_a - m).norm(), d_b = (m - sum_b / area_b).norm();
    out.neighbours.push_back({pair.first, pair.second, s.length, d_a + d_b, d_a, d_b});
  }
  for (const auto& [pair, area] : front_back) out.front_back.push_back({pair.first, pair.second, area});
  return out;
}

}  // namespace radnet::geometry
