#include "geometry/scene/seams.hpp"

#include "geometry/scene/vertex_welder.hpp"

#include <algorithm>
#include <map>

namespace radnet::geometry {
namespace {

Vec3 vec(const Point3& p) { return Vec3(p.x(), p.y(), p.z()); }
Mesh::Vertex_index vertex(int v) { return Mesh::Vertex_index(static_cast<Mesh::size_type>(v)); }

// The vertices joined to v along its surface's border.
std::vector<int> borderNeighbours(const Mesh& mesh, int v) {
  std::vector<int> out;
  for (auto h : CGAL::halfedges_around_target(mesh.halfedge(vertex(v)), mesh))
    if (mesh.is_border(h) || mesh.is_border(mesh.opposite(h)))
      out.push_back(static_cast<int>(mesh.source(h).idx()));
  return out;
}

double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

// A seam point where surface A's rim goes on to a vertex that is on no seam but lies (in
// nominal positions) along B's rim edge from the same point, within a quarter of that
// edge's length of it, yet off that edge where the surfaces are: B's rim has a corner fewer
// there and is curved, so the two rims part between.
void findPartialSeams(const Scene& scene, const std::map<int, std::vector<int>>& seam_points,
                      const std::vector<char>& on_seam, SeamReport& report) {
  const Mesh& mesh = scene.mesh();
  for (const auto& [point, members] : seam_points)
    for (int u : members)
      for (int v : borderNeighbours(mesh, u)) {
        if (on_seam[static_cast<size_t>(v)]) continue;
        const Vec3 pv = scene.nominalPoint(v);
        for (int w : members) {
          if (scene.vertexSurface(w) == scene.vertexSurface(u)) continue;
          for (int x : borderNeighbours(mesh, w)) {
            const Vec3 a = scene.nominalPoint(w), b = scene.nominalPoint(x);
            if (distanceToSegment(pv, a, b) > 0.25 * (b - a).norm()) continue;
            // A straight rim (box faces, panels of other cell counts) has v on B's edge: no slit.
            const double off = distanceToSegment(vec(mesh.point(vertex(v))), vec(mesh.point(vertex(w))),
                                                 vec(mesh.point(vertex(x))));
            if (off <= 1e-6 * (b - a).norm()) continue;
            const int sa = scene.vertexSurface(u), sb = scene.vertexSurface(w);
            const std::pair<int, int> pair{std::min(sa, sb), std::max(sa, sb)};
            if (std::find(report.partial.begin(), report.partial.end(), pair) == report.partial.end())
              report.partial.emplace_back(pair);
          }
        }
      }
}

}  // namespace

std::vector<std::string> partialSeamWarnings(const Scene& scene, const SeamReport& report) {
  std::vector<std::string> out;
  for (const auto& [a, b] : report.partial)
    out.push_back("surfaces '" + scene.surfaceNames()[static_cast<size_t>(a)] + "' and '" +
                  scene.surfaceNames()[static_cast<size_t>(b)] +
                  "' meet at some rim vertices but their rims have different facet counts, so they part between "
                  "them and what they enclose leaks there (a 32-facet lid on an 8-facet can lost 4 % of its emission "
                  "to space): give touching primitives the same angular subdivisions, touching meshes the same rim "
                  "vertices");
  return out;
}

SeamReport closeSeams(Scene& scene) {
  SeamReport report;
  const Mesh& mesh = scene.mesh();
  const int nv = static_cast<int>(mesh.number_of_vertices());
  if (nv == 0) return report;
  // Nominal positions equal within 1e-9 of the scene's size are one seam point; the rows of
  // a grid are far further apart than that.
  VertexWelder welder(1e-9 * std::max(scene.extent(), 1e-300));
  std::map<int, std::vector<int>> at_point;  // seam point → mesh vertices, ordered: deterministic
  for (int v = 0; v < nv; ++v) {
    const Mesh::Vertex_index vi(static_cast<Mesh::size_type>(v));
    if (mesh.is_isolated(vi)) continue;  // a pole or apex row that collapsed: no face uses it
    at_point[welder.id(scene.nominalPoint(v))].push_back(v);
  }
  std::vector<std::pair<int, Vec3>> moves;
  std::map<int, std::vector<int>> seam_points;
  std::vector<char> on_seam(static_cast<size_t>(nv), 0);
  for (const auto& [point, members] : at_point) {
    if (members.size() < 2) continue;
    bool several_surfaces = false, on_border = false, apart = false;
    const Point3& p0 = mesh.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(members.front())));
    Vec3 sum = Vec3::Zero();
    for (int v : members) {
      const Mesh::Vertex_index vi(static_cast<Mesh::size_type>(v));
      several_surfaces |= scene.vertexSurface(v) != scene.vertexSurface(members.front());
      on_border |= mesh.is_border(vi);
      apart |= mesh.point(vi) != p0;
      const Point3& p = mesh.point(vi);
      sum += Vec3(p.x(), p.y(), p.z());
    }
    if (!(several_surfaces && on_border)) continue;
    seam_points.emplace(point, members);
    for (int v : members) on_seam[static_cast<size_t>(v)] = 1;
    if (!apart) continue;
    const Vec3 mean = sum / static_cast<double>(members.size());
    for (int v : members) {
      const Point3& p = mesh.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(v)));
      report.largest_move_m = std::max(report.largest_move_m, (Vec3(p.x(), p.y(), p.z()) - mean).norm());
      moves.emplace_back(v, mean);
    }
  }
  findPartialSeams(scene, seam_points, on_seam, report);
  if (moves.empty()) return report;
  std::vector<double> area_before;
  for (const Node& n : scene.nodes()) area_before.push_back(n.area_m2);
  scene.moveVertices(moves);
  for (size_t i = 0; i < area_before.size(); ++i)
    report.largest_area_change =
        std::max(report.largest_area_change, std::abs(scene.nodes()[i].area_m2 / area_before[i] - 1.0));
  report.vertices_moved = static_cast<int>(moves.size());
  return report;
}

}  // namespace radnet::geometry
