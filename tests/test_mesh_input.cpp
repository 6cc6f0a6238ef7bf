// Meshes as CAD and FE tools write them (issue 29): coincidence without false positives,
// cleaning (degenerate, repeated, welded, cracked, inward), partitions, transforms.
#include "geometry/scene/coincidence.hpp"
#include "geometry/scene/mesh_io.hpp"
#include "geometry/scene/mesh_partition.hpp"
#include "geometry/scene/mesh_repair.hpp"
#include "geometry/scene/primitives.hpp"

#include "temp_dir.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <sstream>

using namespace radnet::geometry;

namespace {

// Coordinates as an STL or a VTK float array stores them.
void roundToFloat(TriangleSoup& s) {
  for (Vec3& v : s.vertices) v = v.cast<float>().cast<double>();
}

// A UV sphere (poles as fans), n_polar × n_azimuth, outward.
TriangleSoup uvSphere(int n_polar, int n_azimuth, double r, const Vec3& c) {
  TriangleSoup s;
  s.vertices.push_back(c + Vec3(0, 0, r));
  for (int i = 1; i < n_polar; ++i)
    for (int j = 0; j < n_azimuth; ++j) {
      const double th = M_PI * i / n_polar, ph = 2 * M_PI * j / n_azimuth;
      s.vertices.push_back(c + r * Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)));
    }
  s.vertices.push_back(c + Vec3(0, 0, -r));
  const int south = static_cast<int>(s.vertices.size()) - 1;
  const auto at = [&](int i, int j) { return 1 + (i - 1) * n_azimuth + (j % n_azimuth); };
  for (int j = 0; j < n_azimuth; ++j) s.triangles.push_back({0, at(1, j), at(1, j + 1)});
  for (int i = 1; i < n_polar - 1; ++i)
    for (int j = 0; j < n_azimuth; ++j) {
      s.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      s.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  for (int j = 0; j < n_azimuth; ++j) s.triangles.push_back({at(n_polar - 1, j), south, at(n_polar - 1, j + 1)});
  return s;
}

// The six faces of a cube of side `size` about c, each an n × n grid, outward, as one soup
// (vertices repeated along the cube's edges, as a mesh exporter writes them per face).
TriangleSoup gridCube(int n, double size, const Vec3& c) {
  TriangleSoup s;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      const int base = static_cast<int>(s.vertices.size()), u = (axis + 1) % 3, w = (axis + 2) % 3;
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3 p = Vec3::Zero();
          p[axis] = sign * size / 2, p[u] = -size / 2 + size * i / n, p[w] = -size / 2 + size * j / n;
          s.vertices.push_back(c + p);
        }
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const int a = base + i * (n + 1) + j, b = a + n + 1;
          if (sign > 0) s.triangles.insert(s.triangles.end(), {{a, b, b + 1}, {a, b + 1, a + 1}});
          else s.triangles.insert(s.triangles.end(), {{a, b + 1, b}, {a, a + 1, b + 1}});
        }
    }
  return s;
}

Scene sceneOf(TriangleSoup soup) {
  cleanMesh(soup);
  Scene s;
  s.addSurface("body", "mesh 'body'", soup, "body", "");
  return s;
}

}  // namespace

TEST_CASE("coincidence: fine meshes at and off the origin, float-rounded, have none, true copies are found") {
  // Each of these was refused before the shared projection frame (a UV sphere of 19,998
  // triangles "holds two coincident triangles", 3e-10 m² of overlap that is not there).
  const Eigen::Matrix3d tilt = (Eigen::AngleAxisd(0.2, Vec3::UnitX()) * Eigen::AngleAxisd(0.3, Vec3::UnitZ())).matrix();
  for (const double offset_m : {0.0, 1.5})
    for (const bool as_float : {false, true}) {
      const Vec3 c = offset_m * Vec3(1.0, -0.7, 0.3);
      TriangleSoup ball = uvSphere(100, 101, 0.15, Vec3::Zero()), cube = gridCube(58, 0.2, Vec3::Zero());
      transformMesh(ball, tilt, c);
      transformMesh(cube, tilt, c);
      if (as_float) roundToFloat(ball), roundToFloat(cube);
      INFO("offset " << offset_m << " m, float " << as_float);
      REQUIRE(ball.triangles.size() == 19998);
      CHECK(coincidentFaces(sceneOf(ball), 16).empty());
      CHECK(coincidentFaces(sceneOf(cube), 16).empty());
    }
  // A finely split flat plate beside a coarser one (T-junctions along their shared edge).
  Scene plates;
  plates.addSurface("a", "a", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 200, 50), "a", "");
  plates.addSurface("b", "b", rectangle(Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 7, 13), "b", "");
  CHECK(coincidentFaces(plates, 16).empty());
  // Two truly coincident plates off the origin, one split differently: found, the overlap
  // summing to the plate's area (every pair below the cap of 10,000).
  Scene twice;
  const Vec3 far(800.0, -300.0, 120.0);
  twice.addSurface("p", "p", rectangle(far, Vec3(0.3, 0, 0), Vec3(0, 0.2, 0), 3, 2), "p", "");
  twice.addSurface("q", "q", rectangle(far, Vec3(0.3, 0, 0), Vec3(0, 0.2, 0), 5, 4), "q", "");
  const auto found = coincidentFaces(twice, 10000);
  double overlap = 0.0;
  for (const Coincidence& c : found) overlap += c.overlap_m2;
  CHECK(overlap == Approx(0.06).epsilon(1e-6));  // relative round-off of coordinates near 800 m
}

TEST_CASE("cleanMesh: degenerate and repeated triangles dropped and counted by the file's face, vertices welded") {
  TriangleSoup s;
  s.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(2, 0, 0),
                Vec3(1 + 1e-9, 1, 0)};  // vertex 5: vertex 2 within the weld tolerance
  s.triangles = {{0, 1, 2}, {0, 1, 4}, {2, 0, 1}, {0, 5, 3}, {1, 4, 2}};
  s.element = {10, 11, 12, 13, 14};
  const MeshReport r = cleanMesh(s);
  CHECK(r.degenerate == 1);  // (0, 1, 4): collinear
  CHECK(r.first_degenerate == 11);
  CHECK(r.duplicate == 1);  // (2, 0, 1) is (0, 1, 2) turned
  CHECK(r.first_duplicate == 12);
  CHECK(r.welded_vertices == 1);
  REQUIRE(s.triangles.size() == 3);
  CHECK(s.element == std::vector<int>{10, 13, 14});
  CHECK(s.vertices.size() == 5);  // 5 welded into 2
  CHECK(r.area_m2 == Approx(1.5).epsilon(1e-12));
  CHECK(r.open_edges == 5);
  CHECK_FALSE(r.nearly_closed);  // a flat sheet: its rim bounds all of its area
  s.vertices[0].x() = std::nan("");
  CHECK_THROWS_WITH(cleanMesh(s), Catch::Contains("vertex 0") && Catch::Contains("non-finite"));
}

TEST_CASE("cleanMesh: closed, inward, cracked and open bodies told apart by the holes their rims bound") {
  TriangleSoup cube = gridCube(4, 1.0, Vec3(3, -2, 7));
  MeshReport out = cleanMesh(cube);
  CHECK(out.nearly_closed);
  CHECK(out.open_edges == 0);
  CHECK(out.wound_against == 0);
  CHECK(out.enclosed_volume_m3 == Approx(1.0).epsilon(1e-12));
  TriangleSoup inward = cube;
  flipWinding(inward);
  CHECK(cleanMesh(inward).enclosed_volume_m3 == Approx(-1.0).epsilon(1e-12));
  // Cracked: the +z face lifted by 0.1 mm (wider than the weld tolerance, 1.7 µm here).
  TriangleSoup cracked = gridCube(4, 1.0, Vec3::Zero());
  const size_t per_face = 25;  // (n + 1)² vertices of each face, +z is the sixth
  for (size_t v = 5 * per_face; v < 6 * per_face; ++v) cracked.vertices[v].z() += 1e-4;
  flipWinding(cracked);
  const MeshReport c = cleanMesh(cracked);
  CHECK(c.open_edges == 32);  // the +z face's rim and the four side faces' top edges
  CHECK(c.open_length_m == Approx(8.0).epsilon(1e-3));
  CHECK(c.hole_area_m2 == Approx(8e-4).epsilon(1e-3));  // two loops, each 4 m long and 0.1 mm across
  CHECK(c.nearly_closed);
  CHECK(c.enclosed_volume_m3 < -0.99);
  // Open: a box without its lid, and a tube (its vector area is zero, its rims are not).
  TriangleSoup lidless = gridCube(4, 1.0, Vec3::Zero());
  lidless.triangles.resize(lidless.triangles.size() - 32);
  CHECK_FALSE(cleanMesh(lidless).nearly_closed);
  TriangleSoup tube = cylinder(Vec3(0, 0, 0), Vec3(0, 0, 1), 0.5, {}, 4, 32);
  CHECK_FALSE(cleanMesh(tube).nearly_closed);
}

TEST_CASE("splitMesh: a cube's faces, a sphere's one face, two bodies' components, the file's elements") {
  TriangleSoup cube = gridCube(3, 1.0, Vec3::Zero());
  cleanMesh(cube);
  const auto faces = splitMesh(cube, MeshNodes::Faces, kDefaultFeatureAngleDeg);
  REQUIRE(faces.size() == 6);
  for (size_t k = 0; k < faces.size(); ++k) {
    CHECK(faces[k].name == std::to_string(k));
    TriangleSoup face = faces[k].soup;
    CHECK(cleanMesh(face).area_m2 == Approx(1.0).epsilon(1e-12));
  }
  TriangleSoup ball = uvSphere(40, 40, 1.0, Vec3::Zero());  // 9° between neighbours
  cleanMesh(ball);
  CHECK(splitMesh(ball, MeshNodes::Faces, 20.0).size() == 1);
  CHECK(splitMesh(ball, MeshNodes::Faces, 2.0).size() > 1);  // 4.5° between rings
  TriangleSoup two = gridCube(2, 1.0, Vec3::Zero());
  const TriangleSoup other = gridCube(2, 1.0, Vec3(5, 0, 0));
  const int base = static_cast<int>(two.vertices.size());
  two.vertices.insert(two.vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto t : other.triangles) two.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  cleanMesh(two);
  CHECK(splitMesh(two, MeshNodes::Components, 0).size() == 2);
  // Elements: a quad fanned into two triangles stays one node, named by its file number.
  TriangleSoup quads;
  quads.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)};
  quads.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  quads.element = {7, 7, 9, 9};
  cleanMesh(quads);
  const auto elements = splitMesh(quads, MeshNodes::Elements, 0);
  REQUIRE(elements.size() == 2);
  CHECK(elements[0].name == "7");
  CHECK(elements[1].name == "9");
  CHECK(elements[1].soup.triangles.size() == 2);
}

TEST_CASE("transformMesh turns about the origin, then places") {
  TriangleSoup s;
  s.vertices = {Vec3(0, 1, 0)};
  transformMesh(s, Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()).matrix(), Vec3(0, 0, 0.05));
  CHECK((s.vertices[0] - Vec3(0, 0, 1.05)).norm() < 1e-15);
}

TEST_CASE("OBJ and PLY vertex normals: one per smooth vertex, none at hard edges or where welding joins two") {
  radnet::test::TempDir dir;
  // An octahedron whose corners carry their radial normals (a coarse sphere): every corner
  // names the same `vn` wherever it is used, so each vertex keeps it.
  std::string smooth = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                       "vn 2 0 0\nvn -1 0 0\nvn 0 1 0\nvn 0 -1 0\nvn 0 0 1\nvn 0 0 -1\n";
  for (const char* f : {"1 3 5", "3 2 5", "2 4 5", "4 1 5", "3 1 6", "2 3 6", "4 2 6", "1 4 6"}) {
    std::istringstream corners(f);
    smooth += "f";
    for (int v; corners >> v;) smooth += " " + std::to_string(v) + "//" + std::to_string(v);
    smooth += "\n";
  }
  const TriangleSoup octahedron = readMesh(dir.write("octahedron.obj", smooth), 1.0);
  REQUIRE(octahedron.normals.size() == 6);
  for (size_t v = 0; v < 6; ++v) {
    CHECK(octahedron.normals[v].norm() == Approx(1.0));  // made unit ("vn 2 0 0")
    CHECK(octahedron.normals[v].dot(octahedron.vertices[v]) == Approx(1.0));
  }
  // A square of two triangles whose shared corners are given different normals (a crease):
  // those corners get none; corners named once keep theirs; a file without `vn` gives none.
  const std::string creased = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0.6 0.8\n"
                              "f 1//1 2//1 3//1\nf 1//2 3//2 4//2\n";
  const TriangleSoup square = readMesh(dir.write("square.obj", creased), 1.0);
  REQUIRE(square.normals.size() == 4);
  CHECK(square.normals[0].isZero());
  CHECK(square.normals[2].isZero());
  CHECK(square.normals[1].isApprox(Vec3(0, 0, 1)));
  CHECK(square.normals[3].isApprox(Vec3(0, 0.6, 0.8)));
  CHECK(readMesh(dir.write("plain.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"), 1.0).normals.empty());
  // PLY gives one normal per vertex (nx, ny, nz), made unit; a PLY without them gives none.
  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\n";
  const std::string ply_faces = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const TriangleSoup ply = readMesh(dir.write("n.ply", ply_head + "property float nx\nproperty float ny\n"
                                                         "property float nz\n" + ply_faces +
                                                         "0 0 0 0 0 2\n1 0 0 0.6 0 0.8\n0 1 0 0 0.6 0.8\n3 0 1 2\n"),
                                    1.0);
  REQUIRE(ply.normals.size() == 3);
  CHECK(ply.normals[0].isApprox(Vec3(0, 0, 1)));
  CHECK(ply.normals[2].isApprox(Vec3(0, 0.6, 0.8), 1e-6));
  CHECK(readMesh(dir.write("plain.ply", ply_head + ply_faces + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), 1.0).normals.empty());
  // Two copies of a corner with different normals welded into one: it keeps none; turning
  // the mesh turns its normals.
  TriangleSoup two;
  two.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 0), Vec3(0, -1, 0)};
  two.triangles = {{0, 1, 2}, {3, 4, 1}};
  two.normals = {Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(0, 0, 1)};
  cleanMesh(two);
  REQUIRE(two.normals.size() == 4);
  CHECK(two.normals[0].isZero());
  CHECK(two.normals[1].isApprox(Vec3(0, 0, 1)));
  transformMesh(two, Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX()).toRotationMatrix(), Vec3(5, 0, 0));
  CHECK(two.normals[1].isApprox(Vec3(0, -1, 0)));
}

TEST_CASE("shading normals: the file's vertex normals interpolated over the facet, facing its side") {
  TriangleSoup soup;
  soup.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  soup.triangles = {{0, 1, 2}};
  // Normals pointing away from the facet's front (+z): the facet's side decides.
  soup.normals = {Vec3(0, 0, -1), Vec3(0.6, 0, -0.8), Vec3(0, 0.6, -0.8)};
  Scene scene;
  scene.addSurface("tri", "tri", soup, "tri", "");
  scene.addSurface("flat", "flat", rectangle(Vec3(3, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), "flat", "");
  REQUIRE(scene.hasSmoothNormal(0));
  CHECK(!scene.hasSmoothNormal(1));  // a surface without normals, after one with
  CHECK(scene.shadingNormal(0, Vec3(1, 0, 0)).isApprox(Vec3(-0.6, 0, 0.8)));  // at a corner: its own
  const Vec3 centroid(1.0 / 3, 1.0 / 3, 0);
  const Vec3 mean = -(soup.normals[0] + soup.normals[1] + soup.normals[2]).normalized();
  CHECK(scene.shadingNormal(0, centroid).isApprox(mean));
  CHECK(scene.shadingNormal(1, Vec3(3.5, 0.5, 0)).isApprox(Vec3(0, 0, 1)));
}
