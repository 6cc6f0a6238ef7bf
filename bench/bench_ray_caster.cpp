// Ray caster benchmark: the SAH hierarchy of geometry/rays/bvh.hpp against CGAL's AABB tree
// (the caster's first tree) on the same rays, one thread, in the same run. Rays leave the
// scene's triangles as view-factor rays do: area-weighted origins, cosine-weighted
// directions about the front normal. Scenes: flat panels (a boxed bus with wings), a
// perforated frame (six thick plates with rows of holes, each hole a walled cylinder: what
// CAD structures look like), and any mesh files (millimetre STL exports, scaled) or case
// files (their whole scene, parts placed by the case's transforms) given.
//
//   bench_ray_caster OUT.md [mesh.stl | case.yaml ...]
#include "bench/bench_support.hpp"
#include "geometry/rays/bvh.hpp"
#include "geometry/scene/mesh_io.hpp"
#include "geometry/scene/primitives.hpp"
#include "cases/config/geometry_case.hpp"
#include "cases/config/yaml_document.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>

using namespace radnet::geometry;
using radnet::bench::since;
using Triangles = std::vector<std::array<Vec3, 3>>;

namespace {

void append(Triangles& out, const TriangleSoup& soup) {
  for (const auto& t : soup.triangles)
    out.push_back({soup.vertices[static_cast<size_t>(t[0])], soup.vertices[static_cast<size_t>(t[1])],
                   soup.vertices[static_cast<size_t>(t[2])]});
}

Triangles panels(int m) {
  Triangles t;
  for (const TriangleSoup& face : boxFaces(Vec3(-0.5, -0.5, -0.5), Vec3(1, 1, 1), m)) append(t, face);
  append(t, rectangle(Vec3(0.6, -0.5, 0.0), Vec3(3, 0, 0), Vec3(0, 1, 0), 3 * m, m));
  append(t, rectangle(Vec3(-0.6, -0.5, 0.0), Vec3(0, 1, 0), Vec3(-3, 0, 0), m, 3 * m));
  return t;
}

// A 0.1 m cube of 3 mm plates, each with holes × holes walled holes (annuli on both faces,
// a cylinder between): small triangles crowd the holes, as on a machined or printed part.
Triangles perforatedFrame(int holes) {
  Triangles t;
  const double size = 0.1, thick = 0.003, pitch = size / holes, r_out = 0.5 * pitch, r_in = 0.3 * pitch;
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {0.0, size - thick}) {
      Vec3 n = Vec3::Zero();
      n[axis] = 1.0;
      for (int i = 0; i < holes; ++i)
        for (int j = 0; j < holes; ++j) {
          Vec3 c;
          c[axis] = side;
          c[(axis + 1) % 3] = (i + 0.5) * pitch;
          c[(axis + 2) % 3] = (j + 0.5) * pitch;
          append(t, disc(c, -n, r_out, r_in, {}, 2, 24));
          append(t, disc(c + thick * n, n, r_out, r_in, {}, 2, 24));
          append(t, cylinder(c, thick * n, r_in, {}, 1, 24));
        }
    }
  return t;
}

struct Ray {
  Vec3 origin, direction;
  int from;
};

std::vector<Ray> viewFactorRays(const Triangles& t, int count) {
  std::vector<double> cdf;
  double total = 0.0;
  for (const auto& v : t) cdf.push_back(total += 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).norm());
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Ray> rays;
  for (int k = 0; k < count; ++k) {
    const size_t i = std::min(t.size() - 1, size_t(std::lower_bound(cdf.begin(), cdf.end(), u(rng) * total) - cdf.begin()));
    const auto& v = t[i];
    const double r = std::sqrt(u(rng)), s = u(rng);
    const Vec3 n = (v[1] - v[0]).cross(v[2] - v[0]).normalized();
    const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
    const double rho = std::sqrt(u(rng)), phi = 2.0 * M_PI * u(rng);
    const Vec3 d = rho * std::cos(phi) * e1 + rho * std::sin(phi) * e2 + std::sqrt(1.0 - rho * rho) * n;
    rays.push_back({(1 - r) * v[0] + r * (1 - s) * v[1] + r * s * v[2] + 1e-12 * n, d, static_cast<int>(i)});
  }
  return rays;
}

using K = CGAL::Simple_cartesian<double>;
using Iterator = std::vector<K::Triangle_3>::const_iterator;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Iterator>>>;

void measure(std::ostringstream& md, const std::string& name, const Triangles& t) {
  const std::vector<Ray> rays = viewFactorRays(t, 400000);
  std::vector<K::Triangle_3> cgal_triangles;
  for (const auto& v : t)
    cgal_triangles.emplace_back(K::Point_3(v[0].x(), v[0].y(), v[0].z()), K::Point_3(v[1].x(), v[1].y(), v[1].z()),
                                K::Point_3(v[2].x(), v[2].y(), v[2].z()));
  auto t0 = std::chrono::steady_clock::now();
  Tree tree(cgal_triangles.cbegin(), cgal_triangles.cend());
  tree.build();
  const double cgal_build = since(t0);
  t0 = std::chrono::steady_clock::now();
  const TriangleBvh bvh(t);
  const double bvh_build = since(t0);
  std::vector<int> cgal_hit(rays.size()), bvh_hit(rays.size());
  t0 = std::chrono::steady_clock::now();
  const auto begin = cgal_triangles.cbegin();
  for (size_t k = 0; k < rays.size(); ++k) {
    const Ray& r = rays[k];
    const K::Ray_3 ray(K::Point_3(r.origin.x(), r.origin.y(), r.origin.z()),
                       K::Vector_3(r.direction.x(), r.direction.y(), r.direction.z()));
    const auto hit = tree.first_intersection(ray, [&](const Iterator& it) { return it - begin == r.from; });
    cgal_hit[k] = hit ? static_cast<int>(hit->second - begin) : -1;
  }
  const double cgal_seconds = since(t0);
  t0 = std::chrono::steady_clock::now();
  for (size_t k = 0; k < rays.size(); ++k) bvh_hit[k] = bvh.firstHit(rays[k].origin, rays[k].direction, rays[k].from).triangle;
  const double bvh_seconds = since(t0);
  const long same = std::inner_product(cgal_hit.begin(), cgal_hit.end(), bvh_hit.begin(), 0L, std::plus<>(),
                                       [](int a, int b) { return a == b ? 1L : 0L; });
  const double n = static_cast<double>(rays.size());
  md << "| " << name << " | " << t.size() << " | " << std::setprecision(3) << cgal_build << " | " << bvh_build << " | "
     << n / cgal_seconds / 1e6 << " M | " << n / bvh_seconds / 1e6 << " M | " << std::setprecision(3)
     << cgal_seconds / bvh_seconds << "× | " << same << "/" << rays.size() << " |\n";
  std::cerr << name << " done\n";
}

}  // namespace

int main(int argc, char** argv) {
  const std::string out_path = argc > 1 ? argv[1] : "docs/ray-caster-benchmark.md";
  std::ostringstream md;
  md << "# Ray caster benchmark\n\nGenerated by `build/bench/bench_ray_caster` (`make bench`). Machine: 2 cores of an "
        "AMD EPYC,\n24 GiB, Debian 12, GCC 12 `-O3 -march=native`. One thread; 400,000 rays a scene leaving\n"
        "its triangles as view-factor rays do; the same rays through CGAL 5.5's AABB tree\n"
        "(`first_intersection`, Simple_cartesian<double>) and radnet's SAH hierarchy (geometry/rays/bvh.hpp).\n"
        "Same hit: the same triangle (rays through a shared edge may pick either of its two).\n";
  if (argc > 2) {
    md << "Files given (meshes read in mm; a case file's whole scene, its parts placed as the case places them):";
    for (int k = 2; k < argc; ++k) md << " `" << std::filesystem::path(argv[k]).filename().string() << "`";
    md << ".\n";
  }
  md << "\n"
     << "| scene | triangles | CGAL build (s) | BVH build (s) | CGAL rays/s | BVH rays/s | speed-up | same hit |\n"
     << "|---|---|---|---|---|---|---|---|\n";
  measure(md, "flat panels (bus and wings)", panels(16));
  measure(md, "flat panels (bus and wings)", panels(51));
  measure(md, "perforated frame, 6 plates × 5 × 5 holes", perforatedFrame(5));
  measure(md, "perforated frame, 6 plates × 12 × 12 holes", perforatedFrame(12));
  for (int k = 2; k < argc; ++k) {
    const std::filesystem::path path(argv[k]);
    Triangles t;
    if (path.extension() == ".yaml") {
      const auto scene_case = radnet::cases::loadGeometryCase(radnet::cases::YamlDocument::load(argv[k]));
      for (const Face& f : scene_case.scene.faces()) t.push_back(f.v);
      measure(md, path.filename().string() + " (case)", t);
    } else {
      append(t, readMesh(argv[k], 0.001));
      measure(md, path.filename().string() + " (mm)", t);
    }
  }
  std::ofstream(out_path) << md.str();
  std::cout << md.str();
}
