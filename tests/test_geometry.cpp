// Primitives, scene validation and mesh files.
#include "geometry/scene/coincidence.hpp"
#include "geometry/scene/mesh_repair.hpp"
#include "geometry/scene/mesh_io.hpp"
#include "geometry/scene/primitives.hpp"
#include "geometry/rays/ray_caster.hpp"
#include "geometry/scene/seams.hpp"
#include "geometry/rays/view_factors.hpp"
#include "geometry/scene/shell.hpp"

#include "temp_dir.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

using namespace radnet::geometry;
using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

using radnet::test::TempDir;

Vec3 meanNormal(const TriangleSoup& soup) {
  Vec3 n = Vec3::Zero();
  for (const auto& t : soup.triangles)
    n += (soup.vertices[t[1]] - soup.vertices[t[0]]).cross(soup.vertices[t[2]] - soup.vertices[t[0]]);
  return n;
}

// Σ over triangles of (centroid − c) · normal × area: > 0 when the fronts face away from c.
double outwardness(const TriangleSoup& soup, const Vec3& c) {
  double s = 0.0;
  for (const auto& t : soup.triangles) {
    const Vec3 a = soup.vertices[t[0]], b = soup.vertices[t[1]], d = soup.vertices[t[2]];
    s += ((a + b + d) / 3 - c).dot((b - a).cross(d - a));
  }
  return s;
}

}  // namespace

TEST_CASE("primitives: exact areas and front sides as documented") {
  const TriangleSoup r = rectangle(Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0), 4, 5);
  CHECK(r.triangles.size() == 40);
  CHECK(soupArea(r) == Approx(6.0).epsilon(1e-14));
  CHECK(meanNormal(r).normalized().z() == Approx(1.0));

  const TriangleSoup t = triangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 5);
  CHECK(t.triangles.size() == 25);
  CHECK(soupArea(t) == Approx(0.5).epsilon(1e-14));
  CHECK(meanNormal(t).z() > 0);

  const TriangleSoup q = quadrilateral({Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0), Vec3(0, 2, 0)}, 3, 3);
  CHECK(soupArea(q) == Approx(3.0).epsilon(1e-14));
  CHECK_THROWS_WITH(quadrilateral({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0.5), Vec3(0, 1, 0)}, 1, 1),
                    Contains("coplanar"));

  const TriangleSoup d = disc(Vec3(0, 0, 1), Vec3(0, 0, -1), 0.5, 0.0, {}, 3, 24);
  CHECK(soupArea(d) == Approx(M_PI * 0.25).epsilon(1e-12));
  CHECK(meanNormal(d).normalized().z() == Approx(-1.0));
  const TriangleSoup annulus = disc(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 0.5, Sweep{0, 90, {}}, 2, 8);
  CHECK(soupArea(annulus) == Approx(0.25 * M_PI * (1 - 0.25)).epsilon(1e-12));
  CHECK(meanNormal(annulus).z() > 0);

  const TriangleSoup cyl = cylinder(Vec3(0, 0, 0), Vec3(0, 0, 2), 0.5, {}, 3, 32);
  CHECK(soupArea(cyl) == Approx(2 * M_PI * 0.5 * 2).epsilon(1e-12));
  CHECK(outwardness(cyl, Vec3(0, 0, 1)) > 0);
  const TriangleSoup cn = cone(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 0.0, {}, 4, 32);
  CHECK(soupArea(cn) == Approx(M_PI * 1.0 * std::sqrt(2.0)).epsilon(1e-9));
  CHECK(outwardness(cn, Vec3(0, 0, 0.25)) > 0);

  const TriangleSoup sph = sphere(Vec3(1, 2, 3), 2.0, Vec3(0, 0, 1), 0, 180, {}, 12, 24);
  CHECK(soupArea(sph) == Approx(16 * M_PI).epsilon(1e-12));
  CHECK(outwardness(sph, Vec3(1, 2, 3)) > 0);
  const TriangleSoup cap = sphere(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 1), 0, 90, Sweep{0, 180, {}}, 6, 12);
  CHECK(soupArea(cap) == Approx(M_PI).epsilon(1e-12));  // quarter sphere: 4π/4

  const auto box = boxFaces(Vec3(0, 0, 0), Vec3(1, 2, 3), 2);
  const Vec3 centre(0.5, 1, 1.5);
  for (int k = 0; k < 6; ++k) CHECK(outwardness(box[k], centre) > 0);
  CHECK(soupArea(box[0]) == Approx(6.0));
  CHECK(soupArea(box[4]) == Approx(2.0));
}

TEST_CASE("primitives reject bad parameters") {
  CHECK_THROWS_AS(rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), 1, 1), GeometryError);
  CHECK_THROWS_AS(rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0, 1), GeometryError);
  CHECK_THROWS_AS(disc(Vec3(0, 0, 0), Vec3(0, 0, 0), 1.0, 0.0, {}, 1, 8), GeometryError);
  CHECK_THROWS_AS(disc(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 1.0, {}, 1, 8), GeometryError);
  CHECK_THROWS_AS(sphere(Vec3(0, 0, 0), -1.0, Vec3(0, 0, 1), 0, 180, {}, 4, 8), GeometryError);
  CHECK_THROWS_AS(cylinder(Vec3(0, 0, 0), Vec3(0, 0, 1), std::nan(""), {}, 1, 8), GeometryError);
  CHECK_THROWS_AS(cone(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 1.0, Sweep{10, 5, {}}, 1, 8), GeometryError);
}

TEST_CASE("scene: nodes per side, areas, and clear errors naming the surface and triangle") {
  Scene s;
  s.addSurface("panel", "rectangle 'panel'", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 2, 0), 2, 2), "panel",
               "panel.back");
  s.addSurface("panel2", "rectangle 'panel2'", rectangle(Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), "panel",
               "");
  REQUIRE(s.nodes().size() == 2);
  CHECK(s.nodes()[0].area_m2 == Approx(3.0));
  CHECK(s.nodes()[1].area_m2 == Approx(2.0));
  CHECK(s.nodes()[1].side == -1);
  CHECK(s.vertexMatrix().rows() == 9 + 4);
  CHECK(s.triangleMatrix().rows() == 10);
  CHECK(s.frontNodes()[9] == 0);
  CHECK(s.backNodes()[9] == -1);

  TriangleSoup bad;
  bad.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 1, 0)};
  bad.triangles = {{0, 1, 3}, {0, 1, 2}};
  CHECK_THROWS_WITH(s.addSurface("x", "mesh 'x' (x.off)", bad, "x", ""),
                    Contains("mesh 'x' (x.off)") && Contains("triangle 1") && Contains("degenerate"));
  bad.vertices[3] = Vec3(0, std::nan(""), 0);
  CHECK_THROWS_WITH(s.addSurface("x", "x", bad, "x", ""), Contains("vertex 3") && Contains("non-finite"));
  TriangleSoup sliver;
  sliver.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0.5, 1e-6, 0)};
  sliver.triangles = {{0, 1, 2}};
  s.addSurface("s", "sliver", sliver, "sliver", "");
  REQUIRE(s.warnings().size() == 1);
  CHECK_THAT(s.warnings()[0], Contains("sliver") && Contains("triangle 0"));
  CHECK_THROWS_WITH(
      s.addSurface("y", "y", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1), "panel.back", ""),
      Contains("front side and for a back side"));
  TriangleSoup flipped;  // two triangles sharing an edge with clashing orientation
  flipped.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  flipped.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 2, 1}};
  // Kept with vertices of its own (rays see it as written), and reported once.
  CHECK_NOTHROW(s.addSurface("z", "mesh 'z'", flipped, "z", ""));
  CHECK(s.faces().size() == 10 + 1 + 3);
  REQUIRE(s.warnings().size() == 2);
  CHECK_THAT(s.warnings()[1], Contains("do not fit their neighbours") && Contains("mesh 'z': 1, first triangle 2"));
}

TEST_CASE("sliver triangles still cast and receive rays correctly") {
  // A unit square made of one normal triangle and a fan of slivers: F to a parallel square
  // must not depend on the triangulation.
  TriangleSoup square;
  square.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  for (int k = 1; k < 200; ++k) square.vertices.push_back(Vec3(1.0 - k / 200.0, 1.0, 0));
  square.triangles.push_back({0, 1, 2});
  int prev = 2;
  for (int k = 0; k < 199; ++k) {
    square.triangles.push_back({0, prev, 4 + k});
    prev = 4 + k;
  }
  square.triangles.push_back({0, prev, 3});
  Scene s;
  s.addSurface("slivers", "slivers", square, "a", "");
  s.addSurface("b", "b", rectangle(Vec3(0, 0, 1), Vec3(0, 1, 0), Vec3(1, 0, 0), 1, 1), "b", "");
  CHECK(s.nodes()[0].area_m2 == Approx(1.0).epsilon(1e-12));
  RayCaster caster(s);
  const Hit hit = caster.firstHit(Vec3(0.3, 0.99, 0.5), Vec3(0, 0, -1));
  CHECK(hit.face > 0);  // one of the slivers, from the front
  CHECK(hit.front);
  CHECK(hit.distance == Approx(0.5));
}

TEST_CASE("mesh files: OFF, OBJ (with groups), STL, PLY read and scaled, bad files are named") {
  TempDir dir;
  const std::string off = dir.write("quad.off", "OFF\n4 1 0\n0 0 0\n1000 0 0\n1000 1000 0\n0 1000 0\n4 0 1 2 3\n");
  const TriangleSoup q = readMesh(off, 0.001);  // mm → m
  CHECK(q.triangles.size() == 2);
  CHECK(soupArea(q) == Approx(1.0));
  const std::string obj = dir.write("two.obj",
                                    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\n"
                                    "g top\nf 1 2 3 4\ng side\nf 1/1/1 2/2/2 6/3/3 5/4/4\n");
  CHECK(soupArea(readMesh(obj, 1.0)) == Approx(2.0));
  const auto groups = readObjGroups(obj, 2.0);
  REQUIRE(groups.size() == 2);
  CHECK(groups[0].name == "top");
  CHECK(groups[1].name == "side");
  CHECK(soupArea(groups[1].soup) == Approx(4.0));
  const std::string stl =
      dir.write("t.stl",
                "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 2 0 0\nvertex 0 2 0\n"
                "endloop\nendfacet\nendsolid t\n");
  CHECK(soupArea(readMesh(stl, 1.0)) == Approx(2.0));
  // Binary STL: 80-byte header, count, 50 bytes per triangle (normal, 3 vertices, attribute).
  auto binaryStl = [&](const std::string& name, std::uint32_t count, int triangles) {
    std::string bytes(80, ' ');
    bytes.append(reinterpret_cast<const char*>(&count), 4);
    for (int t = 0; t < triangles; ++t) {
      const float f[12] = {0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 2, 0};
      bytes.append(reinterpret_cast<const char*>(f), sizeof f);
      bytes.append(2, '\0');
    }
    return dir.write(name, bytes);
  };
  CHECK(soupArea(readMesh(binaryStl("b.stl", 2, 2), 1.0)) == Approx(4.0));
  // A count that disagrees with the size is refused, not read short (issue 13).
  CHECK_THROWS_WITH(readMesh(binaryStl("short.stl", 1, 2), 1.0), Contains("counts 1 triangles"));
  const std::string ply = dir.write("t.ply",
                                    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                    "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  CHECK(soupArea(readMesh(ply, 1.0)) == Approx(0.5));
  // Coordinates not named x, y, z (an exporter's "Z", or none) were read as 0: a tilted
  // triangle flattened without a word (issue 38). Refused, naming what the file has.
  const std::string upper = dir.write("upper.ply",
                                      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float Z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                      "end_header\n0 0 0\n1 0 1\n0 1 1\n3 0 1 2\n");
  CHECK_THROWS_WITH(readMesh(upper, 1.0), Contains("upper.ply") && Contains("no property 'z' (it has: x, y, Z)"));
  CHECK_THROWS_WITH(readMesh(dir.write("open.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"), 1.0),
                    Contains("end_header"));

  const std::string truncated = dir.write("cut.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n");
  CHECK_THROWS_WITH(readMesh(truncated, 1.0), Contains("cut.off") && Contains("truncated"));
  CHECK_THROWS_WITH(readMesh((dir.path / "missing.stl").string(), 1.0),
                    Contains("missing.stl") && Contains("not found"));
  CHECK_THROWS_WITH(readMesh(dir.write("x.dae", "nothing"), 1.0), Contains("unknown mesh format"));
  CHECK_THROWS_WITH(readMesh(off, -1.0), Contains("scale"));
  const std::string bad_index = dir.write("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  CHECK_THROWS_AS(readObjGroups(bad_index, 1.0), GeometryError);
  const std::string garbage = dir.write("garbage.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\ng x\nf 1 two 3\n");
  CHECK_THROWS_WITH(readObjGroups(garbage, 1.0), Contains("garbage.obj:5") && Contains("'two'"));
}

namespace {

// Big-endian bytes of 32-bit values (binary OFF and big-endian PLY).
template <class T>
std::string bigEndian(std::initializer_list<T> values) {
  std::string out;
  for (T v : values) {
    std::uint32_t u;
    std::memcpy(&u, &v, 4);
    for (int k = 3; k >= 0; --k) out.push_back(static_cast<char>((u >> (8 * k)) & 0xff));
  }
  return out;
}

}  // namespace

TEST_CASE("mesh files: binary OFF and PLY are read, corner and list counts beyond the file are refused before reading") {
  TempDir dir;
  const std::string quad = bigEndian<float>({0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0});
  const std::string off = dir.write("b.off", "OFF BINARY\n" + bigEndian<std::int32_t>({4, 2, 0}) + quad +
                                                 bigEndian<std::int32_t>({3, 0, 1, 2, 3, 0, 2, 3}));
  CHECK(soupArea(readMesh(off, 1.0)) == Approx(4.0));
  // Each face's own corner count bounds its allocation (2e9 corners took 15 GB in CGAL).
  CHECK_THROWS_WITH(readMesh(dir.write("c.off", "OFF BINARY\n" + bigEndian<std::int32_t>({4, 1, 0}) + quad +
                                                    bigEndian<std::int32_t>({2000000000, 0, 1, 2})),
                             1.0),
                    Contains("c.off") && Contains("face 0 claims 2000000000 corners"));
  CHECK_THROWS_WITH(readMesh(dir.write("d.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2000000000 0 1 2\n"), 1.0),
                    Contains("d.off") && Contains("face 0 claims 2000000000 corners"));
  const std::string header =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uint int vertex_indices\nproperty float quality\nend_header\n";
  const std::string faces = bigEndian<std::int32_t>({3, 0, 1, 2}) + bigEndian<float>({0.5f}) +
                            bigEndian<std::int32_t>({3, 0, 2, 3}) + bigEndian<float>({0.5f});
  CHECK(soupArea(readMesh(dir.write("b.ply", header + quad + faces), 1.0)) == Approx(4.0));
  const std::string huge = bigEndian<std::uint32_t>({4294967295u, 0, 1, 2}) + bigEndian<float>({0.5f});
  CHECK_THROWS_WITH(readMesh(dir.write("c.ply", header + quad + huge + huge), 1.0),
                    Contains("c.ply") && Contains("face 0 lists 4294967295 entries"));
}

TEST_CASE("shell adjacency: grid neighbours share their edge at the centroid distance, box faces fold at an edge") {
  // A two-sided 0.6 × 0.2 m panel in 3 × 1 node cells (2 × 2 subdivisions each, so the shared
  // boundary is made of two triangle edges): L = 0.2 m, d = 0.2 m between cell centroids.
  Scene panel;
  const Vec3 o(0, 0, 0), u(0.6, 0, 0), v(0, 0.2, 0);
  for (int i = 0; i < 3; ++i) {
    const std::string cell = "c" + std::to_string(i);
    panel.addSurface(cell, cell, rectangle(o + (i / 3.0) * u, u / 3.0, v, 2, 2), cell, cell + ".back");
  }
  const ShellAdjacency adj = shellAdjacency(panel, 0, static_cast<int>(panel.faces().size()));
  REQUIRE(adj.neighbours.size() == 4);  // c0–c1, c1–c2 on each side
  for (const auto& nb : adj.neighbours) {
    CHECK(nb.shared_length_m == Approx(0.2).epsilon(1e-12));
    CHECK(nb.distance_m == Approx(0.2).epsilon(1e-12));
    CHECK(panel.nodes()[static_cast<size_t>(nb.a)].side == panel.nodes()[static_cast<size_t>(nb.b)].side);
  }
  REQUIRE(adj.front_back.size() == 3);
  for (const auto& fb : adj.front_back) CHECK(fb.area_m2 == Approx(0.04).epsilon(1e-12));
  // A 0.3 × 0.1 × 0.1 m box, a node per face: +x and +y meet along a 0.1 m edge; the path
  // runs from each centroid to the edge's midpoint, 0.05 + 0.15 m, not the 0.158 m chord.
  Scene box;
  const auto faces = boxFaces(Vec3(0, 0, 0), Vec3(0.3, 0.1, 0.1), 4);
  for (size_t f = 0; f < 6; ++f) box.addSurface(kBoxFaceNames[f], kBoxFaceNames[f], faces[f], kBoxFaceNames[f], "");
  const ShellAdjacency folds = shellAdjacency(box, 0, static_cast<int>(box.faces().size()));
  CHECK(folds.neighbours.size() == 12);  // a box's 12 edges
  CHECK(folds.front_back.empty());
  const int px = box.nodeIndex("+x"), py = box.nodeIndex("+y");
  bool found = false;
  for (const auto& nb : folds.neighbours)
    if (std::minmax(nb.a, nb.b) == std::minmax(px, py)) {
      found = true;
      CHECK(nb.shared_length_m == Approx(0.1).epsilon(1e-12));
      CHECK(nb.distance_m == Approx(0.2).epsilon(1e-12));
    }
  CHECK(found);
}

TEST_CASE("a closed shell whose fronts face inward has a negative volume, an open cap is not closed") {
  // The warning itself (front named, not a cavity) is the case file's: tests/test_mesh_cases.cpp.
  const TriangleSoup ball = sphere(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 1), 0, 180, {}, 6, 12);
  TriangleSoup outward = ball, inward = ball;
  flipWinding(inward);
  const MeshReport out = cleanMesh(outward), in = cleanMesh(inward);
  CHECK(out.nearly_closed);
  CHECK(in.nearly_closed);
  CHECK(out.enclosed_volume_m3 > 0);
  CHECK(in.enclosed_volume_m3 == Approx(-out.enclosed_volume_m3).epsilon(1e-12));
  TriangleSoup cap = inward;  // a hemisphere is no closed shell
  cap.triangles.resize(cap.triangles.size() / 2);
  CHECK_FALSE(cleanMesh(cap).nearly_closed);
}

TEST_CASE("coincident surfaces: a radiator laid on a face is found, lifted or back to back it is not") {
  const auto withRadiator = [](double lift, bool flipped, const std::string& back) {
    Scene s;
    s.addSurface("face", "rectangle 'face'", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 4, 4), "face", back);
    // 0.6 × 0.6 m on the face; `flipped`: its front faces the other way (−z).
    const TriangleSoup rad = flipped ? rectangle(Vec3(0.2, 0.2, lift), Vec3(0, 0.6, 0), Vec3(0.6, 0, 0), 3, 3)
                                     : rectangle(Vec3(0.2, 0.2, lift), Vec3(0.6, 0, 0), Vec3(0, 0.6, 0), 3, 3);
    s.addSurface("radiator", "rectangle 'radiator'", rad, "radiator", "");
    return coincidentFaces(s, 1000);
  };
  const std::vector<Coincidence> on = withRadiator(0.0, false, "");
  REQUIRE_FALSE(on.empty());
  double overlap = 0.0;
  for (const Coincidence& c : on) overlap += c.overlap_m2;
  CHECK(overlap == Approx(0.36).epsilon(1e-9));  // the radiator's whole area, counted once per pair
  CHECK(withRadiator(1e-3, false, "").empty());   // lifted by 1 mm: two surfaces, rays tell them apart
  CHECK(withRadiator(0.0, true, "").empty());     // back to back: each side sees its own half-space
  CHECK_FALSE(withRadiator(0.0, true, "face.back").empty());  // unless the face's back faces that way too

  // The same triangle in two meshes (a part exported twice): found, its whole area.
  Scene dup;
  const TriangleSoup soup = rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1, 1);
  dup.addSurface("m1", "mesh 'm1'", soup, "m1", "");
  dup.addSurface("m2", "mesh 'm2'", soup, "m2", "");
  const std::vector<Coincidence> twice = coincidentFaces(dup, 1000);
  REQUIRE(twice.size() == 2);  // each of the two triangles, with its copy
  CHECK(twice[0].overlap_m2 + twice[1].overlap_m2 == Approx(1.0).epsilon(1e-12));
  // Adjacent triangles of one rectangle share an edge, not an area.
  Scene plain;
  plain.addSurface("p", "rectangle 'p'", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 20, 20), "p", "p.back");
  CHECK(coincidentFaces(plain).empty());

  // Long thin cells and a large patch across many of them (the grid of boxes: cells of the
  // median box, a face in every cell it reaches, each pair tested once): a strip 40 m × 0.1 m
  // cut 800 × 2 with a 3 m × 0.1 m cover at one end, cut 7 × 3, its area found once in all.
  Scene strip;
  strip.addSurface("strip", "rectangle 'strip'", rectangle(Vec3(0, 0, 0), Vec3(40, 0, 0), Vec3(0, 0.1, 0), 800, 2),
                   "strip", "");
  strip.addSurface("cover", "rectangle 'cover'", rectangle(Vec3(36.5, 0, 0), Vec3(3, 0, 0), Vec3(0, 0.1, 0), 7, 3),
                   "cover", "");
  double covered = 0.0;
  for (const Coincidence& c : coincidentFaces(strip, 100000)) {
    CHECK((c.face_a < 3200) != (c.face_b < 3200));  // one face of each surface: the strip's own pairs share edges only
    covered += c.overlap_m2;
  }
  CHECK(covered == Approx(0.3).epsilon(1e-9));
}

namespace {

// Rays leaving each node that reach space, by 20,000 rays per node.
Eigen::VectorXd spaceFraction(const Scene& scene) {
  const RayCaster caster(scene);
  ViewFactorOptions o;
  o.rays_per_node = 20000;
  o.seed = 3;
  return computeViewFactors(caster, o).space;
}

// A can of radius 1 m, height 1 m, `segments` facets round, closed by two discs: the inside
// (cylinder back, disc fronts) is an enclosure.
Scene closedCan(int segments) {
  Scene s;
  s.addSurface("wall", "cylinder 'wall'", cylinder(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, {}, 1, segments), "", "wall.back");
  s.addSurface("bottom", "disc 'bottom'", disc(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 0.0, {}, 1, segments), "bottom", "");
  s.addSurface("top", "disc 'top'", disc(Vec3(0, 0, 1), Vec3(0, 0, -1), 1.0, 0.0, {}, 1, segments), "top", "");
  return s;
}

}  // namespace

TEST_CASE("seams: a can closed by two discs and a dome on its base disc are enclosures once their rims meet") {
  for (const int segments : {8, 24}) {
    INFO("segments " << segments);
    Scene can = closedCan(segments);
    // Before: each primitive kept its own area by its own radial factor, so the rims are
    // apart by (sqrt(2π/(N sin(2π/N))) − π/(N sin(π/N))) R and the inside sees space there.
    const double n = segments;
    const double gap = std::sqrt(2 * M_PI / (n * std::sin(2 * M_PI / n))) - M_PI / (n * std::sin(M_PI / n));
    const Eigen::VectorXd leak_before = spaceFraction(can);
    CHECK(leak_before.maxCoeff() > 0.2 * gap);  // the slit's share of what the wall sees, order gap/h
    const SeamReport r = closeSeams(can);
    CHECK(r.vertices_moved == 4 * segments);  // both rims of the wall and the rim of each disc
    CHECK(r.largest_move_m == Approx(gap / 2).epsilon(1e-9));
    // Areas move by at most the slit's share: 2πR·gap/2 over a disc's πR² (a bound, not an estimate).
    CHECK(r.largest_area_change > 0);
    CHECK(r.largest_area_change < gap);
    // After: every ray leaving the inside hits the inside (one escaping ray of 20,000 would fail).
    CHECK(spaceFraction(can).maxCoeff() == 0.0);
    // Closing again changes nothing.
    CHECK(closeSeams(can).vertices_moved == 0);
  }
  Scene dome;
  dome.addSurface("dome", "sphere 'dome'", sphere(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 1), 0, 90, {}, 6, 16), "", "dome.in");
  dome.addSurface("base", "disc 'base'", disc(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, 0.0, {}, 2, 16), "base", "");
  CHECK(spaceFraction(dome).maxCoeff() > 1e-4);  // 0.06–0.11 % leaked before
  const SeamReport dome_seams = closeSeams(dome);
  CHECK(dome_seams.vertices_moved == 32);
  CHECK(dome_seams.partial.empty());
  CHECK(spaceFraction(dome).maxCoeff() == 0.0);
}

TEST_CASE("seams: rims of different facet counts meet at their common corners only, and that is said") {
  // A 32-facet lid on an 8-facet can: the lid reaches past the can's flat facets.
  Scene can;
  can.addSurface("wall", "wall", cylinder(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, {}, 1, 8), "", "wall.back");
  can.addSurface("lid", "lid", disc(Vec3(0, 0, 1), Vec3(0, 0, -1), 1.0, 0.0, {}, 1, 32), "lid", "");
  const SeamReport r = closeSeams(can);
  CHECK(r.vertices_moved == 16);  // the can's 8 corners and the lid's 8 vertices at the same angles
  REQUIRE(r.partial.size() == 1);
  CHECK(r.partial[0] == std::pair<int, int>(0, 1));
  const std::vector<std::string> w = partialSeamWarnings(can, r);
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], Contains("'wall' and 'lid'") && Contains("same angular subdivisions"));
  // A quarter disc's straight edges end at its centre, which is on no other rim: no warning.
  Scene quarter;
  quarter.addSurface("wall", "wall", cylinder(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, {0, 90, {}}, 1, 4), "", "wall.back");
  quarter.addSurface("lid", "lid", disc(Vec3(0, 0, 1), Vec3(0, 0, -1), 1.0, 0.0, {0, 90, Vec3(1, 0, 0)}, 1, 4), "lid", "");
  CHECK(closeSeams(quarter).partial.empty());
  // Flat panels of different cell counts along a box edge: their vertices lie on each other's
  // straight edges, so nothing parts.
  Scene flat;
  flat.addSurface("face", "face", rectangle(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 2, 2), "face", "");
  flat.addSurface("wing", "wing", rectangle(Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), 6, 3), "wing", "");
  CHECK(closeSeams(flat).partial.empty());
}

TEST_CASE("seams: surfaces that only touch where they were put, or whose exact surfaces only come near, are left alone") {
  // Box faces share their edges exactly: nothing to close.
  Scene box;
  const auto faces = boxFaces(Vec3(0, 0, 0), Vec3(1, 1, 1), 2);
  for (int f = 0; f < 6; ++f) box.addSurface(kBoxFaceNames[f], kBoxFaceNames[f], faces[static_cast<size_t>(f)], kBoxFaceNames[f], "");
  CHECK(closeSeams(box).vertices_moved == 0);
  // A disc 1 mm above a can's rim: its exact rim is not the can's, so the slit is the user's.
  Scene lifted;
  lifted.addSurface("wall", "wall", cylinder(Vec3(0, 0, 0), Vec3(0, 0, 1), 1.0, {}, 1, 8), "", "wall.back");
  lifted.addSurface("lid", "lid", disc(Vec3(0, 0, 1.001), Vec3(0, 0, -1), 1.0, 0.0, {}, 1, 8), "lid", "");
  CHECK(closeSeams(lifted).vertices_moved == 0);
  // Two concentric spheres: their nominal vertices never meet.
  Scene spheres;
  spheres.addSurface("in", "in", sphere(Vec3(0, 0, 0), 1.0, Vec3(0, 0, 1), 0, 180, {}, 6, 12), "in", "");
  spheres.addSurface("out", "out", sphere(Vec3(0, 0, 0), 2.0, Vec3(0, 0, 1), 0, 180, {}, 6, 12), "", "out.in");
  CHECK(closeSeams(spheres).vertices_moved == 0);
}
