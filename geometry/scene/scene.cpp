#include "geometry/scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace radnet::geometry {

namespace {

// Room for `more` faces: one growth for a large surface, still geometric over many small
// ones (an exact reserve per surface copied every face at every surface: 10,000 node
// surfaces took 2.5 s more).
void roomFor(std::vector<Face>& faces, size_t more) {
  if (faces.capacity() < faces.size() + more) faces.reserve(std::max(faces.size() + more, 2 * faces.capacity()));
}

// The soup's triangles as faces (normal, area), after checking every vertex is finite,
// every index valid and no triangle degenerate; slivers are counted (and the first named).
std::vector<Face> checkedFaces(const TriangleSoup& soup, const std::string& label, int& slivers, int& first_sliver) {
  for (size_t i = 0; i < soup.vertices.size(); ++i)
    if (!soup.vertices[i].allFinite()) {
      std::ostringstream s;
      s << label << ": vertex " << i << " has a non-finite coordinate";
      throw GeometryError(s.str());
    }
  // Reference length for the degeneracy test: the surface's own bounding box.
  Vec3 lo = soup.vertices.front(), hi = lo;
  for (const auto& v : soup.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const double size = (hi - lo).norm();
  std::vector<Face> added;
  slivers = 0, first_sliver = -1;
  for (size_t t = 0; t < soup.triangles.size(); ++t) {
    const auto& tri = soup.triangles[t];
    Face f;
    for (int k = 0; k < 3; ++k) {
      const int idx = tri[static_cast<size_t>(k)];
      if (idx < 0 || idx >= static_cast<int>(soup.vertices.size())) {
        std::ostringstream s;
        s << label << ": triangle " << t << " refers to vertex " << idx << " of " << soup.vertices.size();
        throw GeometryError(s.str());
      }
      f.v[static_cast<size_t>(k)] = soup.vertices[static_cast<size_t>(idx)];
    }
    const Vec3 cross = (f.v[1] - f.v[0]).cross(f.v[2] - f.v[0]);
    const double twice_area = cross.norm();
    // Degenerate: area below what double rounding of the coordinates can resolve.
    if (!(twice_area > 1e-12 * size * size)) {
      std::ostringstream s;
      s << label << ": triangle " << t << " (vertices " << tri[0] << ", " << tri[1] << ", " << tri[2]
        << ") is degenerate (area " << 0.5 * twice_area << " m²)";
      throw GeometryError(s.str());
    }
    const double longest2 =
        std::max({(f.v[1] - f.v[0]).squaredNorm(), (f.v[2] - f.v[1]).squaredNorm(), (f.v[0] - f.v[2]).squaredNorm()});
    if (longest2 / twice_area > 1e4 && slivers++ == 0) first_sliver = static_cast<int>(t);
    f.normal = cross / twice_area;
    f.area_m2 = 0.5 * twice_area;
    added.push_back(f);
  }
  return added;
}

}  // namespace

int Scene::nodeIndex(const std::string& name) const {
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (nodes_[i].name == name) return static_cast<int>(i);
  return -1;
}

int Scene::nodeFor(const std::string& name, int side, const std::string& label) {
  if (name.empty()) return -1;
  const int existing = nodeIndex(name);
  if (existing >= 0) {
    if (nodes_[static_cast<size_t>(existing)].side != side)
      throw GeometryError(label + ": node '" + name + "' is used for a front side and for a back side; a node " +
                          "collects sides of one kind");
    return existing;
  }
  nodes_.push_back(Node{name, 0.0, {}, side});
  return static_cast<int>(nodes_.size() - 1);
}

Mesh::Face_index Scene::addLooseFace(const Face& f, const TriangleSoup& soup, const std::array<int, 3>& tri) {
  // An edge of a third triangle, or one wound against its neighbour, which CGAL's
  // Surface_mesh refuses: the triangle keeps vertices of its own (rays see it as written)
  // and the caller reports the defect.
  const bool has_nominal = soup.nominal.size() == soup.vertices.size();
  std::array<Mesh::Vertex_index, 3> own;
  for (size_t k = 0; k < 3; ++k) {
    own[k] = mesh_.add_vertex(Point3(f.v[k].x(), f.v[k].y(), f.v[k].z()));
    const size_t from = static_cast<size_t>(tri[k]);
    nominal_.push_back(has_nominal ? soup.nominal[from] : soup.vertices[from]);
    vertex_surface_.push_back(f.surface);
  }
  return mesh_.add_face(own[0], own[1], own[2]);
}

void Scene::addSurface(const std::string& surface, const std::string& label, const TriangleSoup& soup,
                       const std::string& front_node, const std::string& back_node) {
  if (soup.triangles.empty()) throw GeometryError(label + ": no triangles");
  if (!front_node.empty() && front_node == back_node)
    throw GeometryError(label + ": front and back sides cannot be the same node '" + front_node + "'");
  int slivers = 0, first_sliver = -1;
  std::vector<Face> added = checkedFaces(soup, label, slivers, first_sliver);
  if (slivers > 0)
    noteDefect("sliver triangles (aspect ratio above 1e4), kept",
               label + ": " + std::to_string(slivers) + ", first triangle " + std::to_string(first_sliver));
  const int surface_id = static_cast<int>(surfaces_.size());
  surfaces_.push_back(surface);
  labels_.push_back(label);
  shapes_.push_back(soup.shape);
  first_face_.push_back(static_cast<int>(faces_.size()));
  const int front = nodeFor(front_node, +1, label);
  const int back = nodeFor(back_node, -1, label);
  // Surfaces keep their own vertices in the mesh: panels of different surfaces may touch
  // without forming a manifold, and each surface stays one connected piece.
  std::vector<Mesh::Vertex_index> vids;
  for (const auto& v : soup.vertices) vids.push_back(mesh_.add_vertex(Point3(v.x(), v.y(), v.z())));
  const bool has_nominal = soup.nominal.size() == soup.vertices.size();
  for (size_t k = 0; k < soup.vertices.size(); ++k) {
    nominal_.push_back(has_nominal ? soup.nominal[k] : soup.vertices[k]);
    vertex_surface_.push_back(surface_id);
  }
  // Looked up by name each time: a stored handle would dangle when the scene is copied.
  auto face_id = mesh_.add_property_map<Mesh::Face_index, int>("f:radnet_face", -1).first;
  int misfits = 0, first_misfit = -1;
  roomFor(faces_, added.size());
  for (size_t t = 0; t < added.size(); ++t) {
    Face& f = added[t];
    f.front_node = front;
    f.back_node = back;
    f.surface = surface_id;
    const int id = static_cast<int>(faces_.size());
    const auto& tri = soup.triangles[t];
    Mesh::Face_index fi = mesh_.add_face(vids[static_cast<size_t>(tri[0])], vids[static_cast<size_t>(tri[1])],
                                               vids[static_cast<size_t>(tri[2])]);
    if (fi == Mesh::null_face()) {
      if (misfits++ == 0) first_misfit = static_cast<int>(t);
      fi = addLooseFace(f, soup, tri);
    }
    face_id[fi] = id;
    if (front >= 0) {
      nodes_[static_cast<size_t>(front)].faces.push_back(id);
      nodes_[static_cast<size_t>(front)].area_m2 += f.area_m2;
    }
    if (back >= 0) {
      nodes_[static_cast<size_t>(back)].faces.push_back(id);
      nodes_[static_cast<size_t>(back)].area_m2 += f.area_m2;
    }
    faces_.push_back(f);
  }
  keepCornerNormals(soup);
  if (misfits > 0)
    noteDefect("triangles that do not fit their neighbours (on an edge of three or more triangles, or wound against "
               "a neighbour), kept with their sides as written: check the winding",
               label + ": " + std::to_string(misfits) + ", first triangle " + std::to_string(first_misfit));
}

void Scene::noteDefect(const std::string& kind, const std::string& where) {
  auto it = std::find_if(defects_.begin(), defects_.end(), [&](const auto& d) { return d.first == kind; });
  if (it == defects_.end()) it = defects_.insert(defects_.end(), {kind, {}});
  it->second.push_back(where);
}

std::vector<std::string> Scene::warnings() const {
  constexpr size_t kNamedPlaces = 8;  // beyond these, a count: a 500-part assembly stays one line
  std::vector<std::string> out;
  for (const auto& [kind, places] : defects_) {
    std::string line = kind + ": ";
    for (size_t k = 0; k < places.size() && k < kNamedPlaces; ++k) line += (k ? "; " : "") + places[k];
    if (places.size() > kNamedPlaces) line += "; and " + std::to_string(places.size() - kNamedPlaces) + " more surfaces";
    out.push_back(line);
  }
  return out;
}

void Scene::validate() const {
  if (nodes_.empty()) throw GeometryError("the scene has no thermal nodes");
  for (const auto& n : nodes_)
    if (!(n.area_m2 > 0)) throw GeometryError("node '" + n.name + "' has zero area");
}

Eigen::MatrixXd Scene::vertexMatrix() const {
  Eigen::MatrixXd v(static_cast<Eigen::Index>(mesh_.number_of_vertices()), 3);
  for (auto vi : mesh_.vertices()) {
    const Point3& p = mesh_.point(vi);
    v.row(static_cast<Eigen::Index>(vi.idx())) << p.x(), p.y(), p.z();
  }
  return v;
}

Eigen::MatrixXi Scene::triangleMatrix() const {
  Eigen::MatrixXi t(static_cast<Eigen::Index>(faces_.size()), 3);
  const auto face_id = mesh_.property_map<Mesh::Face_index, int>("f:radnet_face").first;
  for (auto fi : mesh_.faces()) {
    int k = 0;
    const int id = face_id[fi];
    for (auto vi : CGAL::vertices_around_face(mesh_.halfedge(fi), mesh_)) t(id, k++) = static_cast<int>(vi.idx());
  }
  return t;
}

Eigen::VectorXi Scene::frontNodes() const {
  Eigen::VectorXi out(static_cast<Eigen::Index>(faces_.size()));
  for (size_t i = 0; i < faces_.size(); ++i) out[static_cast<Eigen::Index>(i)] = faces_[i].front_node;
  return out;
}

Eigen::VectorXi Scene::backNodes() const {
  Eigen::VectorXi out(static_cast<Eigen::Index>(faces_.size()));
  for (size_t i = 0; i < faces_.size(); ++i) out[static_cast<Eigen::Index>(i)] = faces_[i].back_node;
  return out;
}

void Scene::moveVertices(const std::vector<std::pair<int, Vec3>>& moves) {
  if (moves.empty()) return;
  for (const auto& [v, p] : moves) mesh_.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(v))) = Point3(p.x(), p.y(), p.z());
  const Eigen::MatrixXi tri = triangleMatrix();
  for (auto& n : nodes_) n.area_m2 = 0.0;
  for (size_t i = 0; i < faces_.size(); ++i) {
    Face& f = faces_[i];
    for (int k = 0; k < 3; ++k) {
      const Point3& p = mesh_.point(Mesh::Vertex_index(static_cast<Mesh::size_type>(tri(static_cast<Eigen::Index>(i), k))));
      f.v[static_cast<size_t>(k)] = Vec3(p.x(), p.y(), p.z());
    }
    const Vec3 cross = (f.v[1] - f.v[0]).cross(f.v[2] - f.v[0]);
    const double twice_area = cross.norm();
    if (!(twice_area > 0) || cross.dot(f.normal) <= 0) {
      std::ostringstream s;
      s << "surface '" << surfaces_[static_cast<size_t>(f.surface)] << "': triangle " << i
        << " degenerates or flips where its seam with another surface is closed";
      throw GeometryError(s.str());
    }
    f.normal = cross / twice_area;
    f.area_m2 = 0.5 * twice_area;
    if (f.front_node >= 0) nodes_[static_cast<size_t>(f.front_node)].area_m2 += f.area_m2;
    if (f.back_node >= 0) nodes_[static_cast<size_t>(f.back_node)].area_m2 += f.area_m2;
  }
}

double Scene::extent() const {
  if (faces_.empty()) return 0.0;
  Vec3 lo = faces_.front().v[0], hi = lo;
  for (const auto& f : faces_)
    for (const auto& v : f.v) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  return (hi - lo).maxCoeff();
}

Vec3 CurvedShape::normalAt(const Vec3& p, const Vec3& facet_normal) const {
  Vec3 n = Vec3::Zero();
  if (kind == Kind::Sphere) {
    n = p - center;
  } else if (kind == Kind::Cone) {
    // r(h) linear along the axis: the outward normal ∝ r̂ − (dr/dh) â.
    const Vec3 d = p - center;
    const Vec3 radial = d - d.dot(axis) * axis;
    const double r = radial.norm();
    if (r > 0) n = radial / r - slope * axis;
  }
  const double len = n.norm();
  if (!(len > 0)) return facet_normal;
  n /= len;
  return n.dot(facet_normal) >= 0 ? n : Vec3(-n);
}

void Scene::keepCornerNormals(const TriangleSoup& soup) {
  const bool has_normals = soup.normals.size() == soup.vertices.size();
  if (!has_normals && corner_normals_.empty()) return;  // no surface so far has any
  corner_normals_.resize(faces_.size() - soup.triangles.size());  // earlier surfaces: zeros
  for (const auto& tri : soup.triangles) {
    std::array<Vec3, 3> corners{Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
    if (has_normals)
      for (size_t k = 0; k < 3; ++k) corners[k] = soup.normals[static_cast<size_t>(tri[k])];
    corner_normals_.push_back(corners);
  }
}

bool Scene::hasSmoothNormal(int f) const {
  const Face& face = faces_[static_cast<size_t>(f)];
  if (shapes_[static_cast<size_t>(face.surface)].kind != CurvedShape::Kind::None) return true;
  if (corner_normals_.empty()) return false;
  const auto& c = corner_normals_[static_cast<size_t>(f)];
  return c[0].squaredNorm() > 0 && c[1].squaredNorm() > 0 && c[2].squaredNorm() > 0;
}

Vec3 Scene::shadingNormal(int f, const Vec3& p) const {
  const Face& face = faces_[static_cast<size_t>(f)];
  const CurvedShape& shape = shapes_[static_cast<size_t>(face.surface)];
  if (shape.kind != CurvedShape::Kind::None || !hasSmoothNormal(f)) return shape.normalAt(p, face.normal);
  // Phong: the corners' normals weighted by p's barycentric coordinates in the facet.
  const auto& c = corner_normals_[static_cast<size_t>(f)];
  const Vec3 e1 = face.v[1] - face.v[0], e2 = face.v[2] - face.v[0], d = p - face.v[0];
  const double d11 = e1.dot(e1), d12 = e1.dot(e2), d22 = e2.dot(e2), d1 = d.dot(e1), d2 = d.dot(e2);
  const double det = d11 * d22 - d12 * d12;
  if (!(det > 0)) return face.normal;
  const double b1 = std::clamp((d22 * d1 - d12 * d2) / det, 0.0, 1.0);
  const double b2 = std::clamp((d11 * d2 - d12 * d1) / det, 0.0, 1.0 - b1);
  const Vec3 n = (1.0 - b1 - b2) * c[0] + b1 * c[1] + b2 * c[2];
  const double len = n.norm();
  if (!(len > 0)) return face.normal;
  // The file's normals may face either way of our winding: the facet's side decides.
  return n.dot(face.normal) >= 0 ? Vec3(n / len) : Vec3(-n / len);
}

}  // namespace radnet::geometry
