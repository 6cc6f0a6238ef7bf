#pragma once
// A spacecraft scene: triangles in a CGAL Surface_mesh, each triangle carrying the thermal
// node of its front side and of its back side (or none: an inactive side). Panels are
// thin shells whose two faces are different nodes (solar cells in front, paint behind).
// geometry/ knows nothing of orbits or YAML.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <Eigen/Dense>

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace radnet::geometry {

using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point3>;
using Vec3 = Eigen::Vector3d;

/// Bad geometry: the message names the surface (and file) and the triangle.
class GeometryError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Triangles of one surface before they join a scene (vertices in metres).
struct TriangleSoup {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  /// Where each vertex lies on the exact surface, before an area-preserving primitive moved
  /// it off (geometry/scene/primitives.hpp); empty: the vertices themselves. Two surfaces whose
  /// nominal vertices coincide meet there by design (geometry/scene/seams.hpp).
  std::vector<Vec3> nominal;
};

/// A thermal node: a set of triangle sides.
struct Node {
  std::string name;
  double area_m2 = 0.0;
  std::vector<int> faces;  ///< scene face indices
  int side = +1;           ///< +1: the faces' front sides, −1: their back sides
};

/// What the scene knows of one triangle, flat for the ray-casting hot loops.
struct Face {
  std::array<Vec3, 3> v;
  Vec3 normal;  ///< unit, towards the front side ((v1 − v0) × (v2 − v0))
  double area_m2 = 0.0;
  int front_node = -1;  ///< node of the front side, −1: inactive
  int back_node = -1;   ///< node of the back side, −1: inactive
  int surface = -1;     ///< index into Scene::surfaceNames()
};

class Scene {
 public:
  /// Adds the triangles of one surface. Sides name a node ("" = inactive side; both
  /// inactive: an occluder that blocks rays and belongs to no node); a node
  /// named again on another surface collects those triangles too (it must be the same side
  /// kind or the message says so). Degenerate triangles are rejected naming the triangle;
  /// slivers (aspect ratio > 1e4) are accepted and listed in warnings().
  /// @param label  how messages name the surface (e.g. "mesh 'antenna' (parts/a.stl)")
  void addSurface(const std::string& surface, const std::string& label, const TriangleSoup& soup,
                  const std::string& front_node, const std::string& back_node);

  /// Checks the finished scene: at least one node, no node of zero area.
  void validate() const;

  const std::vector<Face>& faces() const { return faces_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<std::string>& surfaceNames() const { return surfaces_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  const Mesh& mesh() const { return mesh_; }
  int nodeIndex(const std::string& name) const;

  /// Vertices (nv×3, m), triangles (nt×3, 0-based) and the node of each triangle's front
  /// side (−1: inactive) and back side, for output.
  Eigen::MatrixXd vertexMatrix() const;
  Eigen::MatrixXi triangleMatrix() const;
  Eigen::VectorXi frontNodes() const;
  Eigen::VectorXi backNodes() const;

  /// Longest extent of the bounding box, m (scale for ray offsets and tolerances).
  double extent() const;

  /// Mesh vertex v's nominal position (TriangleSoup::nominal) and the surface it belongs to.
  const Vec3& nominalPoint(int v) const { return nominal_[static_cast<size_t>(v)]; }
  int vertexSurface(int v) const { return vertex_surface_[static_cast<size_t>(v)]; }

  /// Moves mesh vertices (index, new position in m) and updates every face on them, its
  /// normal and area, and the nodes' areas.
  /// @throws GeometryError when a moved triangle degenerates or flips
  void moveVertices(const std::vector<std::pair<int, Vec3>>& moves);

 private:
  int nodeFor(const std::string& name, int side, const std::string& label);

  Mesh mesh_;
  std::vector<Face> faces_;
  std::vector<Node> nodes_;
  std::vector<std::string> surfaces_;
  std::vector<std::string> warnings_;
  std::vector<Vec3> nominal_;        ///< per mesh vertex
  std::vector<int> vertex_surface_;  ///< per mesh vertex
};

}  // namespace radnet::geometry
