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

/// The exact curved surface a primitive's triangles approximate, where it is known: specular
/// reflection uses its normal at the hit point, not the facet's (a facetted sphere mirror
/// scatters like a disco ball; docs/geometry.md, "Specular surfaces").
struct CurvedShape {
  enum class Kind { None, Sphere, Cone };  ///< Cone: any frustum, a cylinder included
  Kind kind = Kind::None;
  Vec3 center = Vec3::Zero();  ///< the sphere's centre, or the cone's base centre, m
  Vec3 axis = Vec3::UnitZ();   ///< the cone's unit axis (base towards top)
  /// The cone's dr/dh: (top radius − base radius) / height, –
  double slope = 0.0;
  /// The unit normal of the exact surface at `p`, on the side `facet_normal` points to.
  Vec3 normalAt(const Vec3& p, const Vec3& facet_normal) const;
};

/// Triangles of one surface before they join a scene (vertices in metres).
struct TriangleSoup {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  /// Where each vertex lies on the exact surface, before an area-preserving primitive moved
  /// it off (geometry/scene/primitives.hpp); empty: the vertices themselves. Two surfaces whose
  /// nominal vertices coincide meet there by design (geometry/scene/seams.hpp).
  std::vector<Vec3> nominal;
  /// The file's face (polygon, FE element) each triangle came from, 0-based; empty: each
  /// triangle is its own face. Meshes split per element and messages use it.
  std::vector<int> element;
  CurvedShape shape;  ///< the exact surface, where a primitive knows it
  /// Per vertex, the unit surface normal the file gives (OBJ `vn`); empty: none. A zero
  /// vector where the file gives a vertex several normals (a hard edge): the triangles on it
  /// keep their facet normal. Specular reflection interpolates them (Scene::shadingNormal).
  std::vector<Vec3> normals;
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
  /// kind or the message says so). Degenerate triangles are rejected naming the triangle
  /// (meshes from files are cleaned first: geometry/scene/mesh_repair.hpp); slivers (aspect
  /// ratio > 1e4) and triangles that do not fit their neighbours (an edge of three or more
  /// triangles, or wound against a neighbour: kept with their own vertices) are noted as defects.
  /// @param label  how messages name the surface (e.g. "mesh 'antenna' (parts/a.stl)")
  void addSurface(const std::string& surface, const std::string& label, const TriangleSoup& soup,
                  const std::string& front_node, const std::string& back_node);

  /// Checks the finished scene: at least one node, no node of zero area.
  void validate() const;

  const std::vector<Face>& faces() const { return faces_; }
  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<std::string>& surfaceNames() const { return surfaces_; }
  /// What was accepted but looks wrong: one line per kind of defect (over every surface that
  /// has it, so a six-part assembly gets one line, not six), then the other warnings.
  std::vector<std::string> warnings() const;
  /// Records one surface's instance of a kind of defect. @param kind the sentence that heads
  /// the kind's line; @param where the surface and what was found there
  void noteDefect(const std::string& kind, const std::string& where);
  /// How messages name surface s (e.g. "mesh 'antenna' from parts/a.stl"), and its first face.
  const std::string& surfaceLabel(int s) const { return labels_[static_cast<size_t>(s)]; }
  int surfaceFirstFace(int s) const { return first_face_[static_cast<size_t>(s)]; }
  const Mesh& mesh() const { return mesh_; }
  int nodeIndex(const std::string& name) const;

  /// Vertices (nv×3, m), triangles (nt×3, 0-based) and the node of each triangle's front
  /// side (−1: inactive) and back side, for output.
  Eigen::MatrixXd vertexMatrix() const;
  Eigen::MatrixXi triangleMatrix() const;
  Eigen::VectorXi frontNodes() const;
  Eigen::VectorXi backNodes() const;

  /// The unit normal at point p of face f, on its front side: the exact curved surface's
  /// where the face's surface has one (CurvedShape), the file's vertex normals interpolated
  /// (Phong) where all three corners have one, else the facet's.
  Vec3 shadingNormal(int f, const Vec3& p) const;
  /// Whether face f reflects about more than its facet normal (a curved primitive's exact
  /// normal, or the file's vertex normals).
  bool hasSmoothNormal(int f) const;

  /// Longest extent of the bounding box, m (scale for ray offsets and tolerances).
  double extent() const;

  /// Mesh vertex v's nominal position (TriangleSoup::nominal) and the surface it belongs to.
  const Vec3& nominalPoint(int v) const { return nominal_[static_cast<size_t>(v)]; }
  int vertexSurface(int v) const { return vertex_surface_[static_cast<size_t>(v)]; }

  /// Moves mesh vertices (index, new position in m) and updates every face on them, its
  /// normal and area, and the nodes' areas.
  /// @throws GeometryError when a moved triangle degenerates or flips
  void moveVertices(const std::vector<std::pair<int, Vec3>>& moves);

  /// Turns surfaces rigidly (an articulated part: docs/geometry.md, "Moving parts"): their
  /// vertices, facet normals, file normals and exact shapes rotate by `angle_rad`,
  /// right-handed about the line through `point` (m) along the unit `axis`. Areas keep.
  /// @param surfaces  indices into surfaceNames()
  void rotateSurfaces(const std::vector<int>& surfaces, const Vec3& point, const Vec3& axis, double angle_rad);

 private:
  int nodeFor(const std::string& name, int side, const std::string& label);
  /// Adds face f (its surface set) with vertices of its own: one CGAL refused to join.
  /// Appends the corner normals of the faces addSurface just added from `soup`.
  void keepCornerNormals(const TriangleSoup& soup);
  Mesh::Face_index addLooseFace(const Face& f, const TriangleSoup& soup, const std::array<int, 3>& tri);

  Mesh mesh_;
  std::vector<Face> faces_;
  std::vector<Node> nodes_;
  std::vector<std::string> surfaces_;
  std::vector<std::pair<std::string, std::vector<std::string>>> defects_;  ///< kind → where, in order met
  std::vector<std::string> labels_;  ///< per surface
  std::vector<int> first_face_;      ///< per surface
  std::vector<CurvedShape> shapes_;  ///< per surface
  /// Per face, its corners' normals from the file (TriangleSoup::normals); empty until a
  /// surface brings some, then one entry per face (zeros: none).
  std::vector<std::array<Vec3, 3>> corner_normals_;
  std::vector<Vec3> nominal_;        ///< per mesh vertex
  std::vector<int> vertex_surface_;  ///< per mesh vertex
};

}  // namespace radnet::geometry
