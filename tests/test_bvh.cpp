// The ray caster's bounding volume hierarchy against a second method: CGAL's AABB tree (the
// caster's first tree), ray for ray, on cluttered and degenerate scenes.
#include "geometry/rays/bvh.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <random>
#include <vector>

using radnet::geometry::TriangleBvh;
using radnet::geometry::Vec3;
using Triangles = std::vector<std::array<Vec3, 3>>;

namespace {

using K = CGAL::Simple_cartesian<double>;
using Iterator = std::vector<K::Triangle_3>::const_iterator;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Iterator>>>;

// CGAL's nearest hit: triangle index and ray parameter (unit direction), or nothing.
struct Reference {
  explicit Reference(const Triangles& triangles) {
    for (const auto& t : triangles)
      cgal.emplace_back(K::Point_3(t[0].x(), t[0].y(), t[0].z()), K::Point_3(t[1].x(), t[1].y(), t[1].z()),
                        K::Point_3(t[2].x(), t[2].y(), t[2].z()));
    tree.insert(cgal.cbegin(), cgal.cend());
    tree.build();
  }
  std::optional<std::pair<int, double>> firstHit(const Vec3& o, const Vec3& d, int skip = -1) const {
    const K::Ray_3 ray(K::Point_3(o.x(), o.y(), o.z()), K::Vector_3(d.x(), d.y(), d.z()));
    const auto begin = cgal.cbegin();
    const auto hit = tree.first_intersection(ray, [&](const Iterator& it) { return it - begin == skip; });
    if (!hit) return std::nullopt;
    const K::Point_3* p = boost::get<K::Point_3>(&hit->first);
    if (!p) return std::nullopt;  // a ray in a triangle's plane: not a hit for radiation
    return std::make_pair(static_cast<int>(hit->second - begin), (Vec3(p->x(), p->y(), p->z()) - o).norm());
  }
  std::vector<K::Triangle_3> cgal;
  Tree tree;
};

Vec3 randomDirection(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Vec3(g(rng), g(rng), g(rng)).normalized();
}

// Clutter: `n` random triangles of size ~`size` in the unit cube, and a closed unit box
// split into 8 × 8 squares a face (axis-aligned, shared edges, zero-thickness boxes).
Triangles clutter(int n, double size, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Triangles t;
  for (int i = 0; i < n; ++i) {
    const Vec3 c(u(rng), u(rng), u(rng));
    t.push_back({c, c + size * randomDirection(rng), c + size * randomDirection(rng)});
  }
  const int k = 8;
  for (int axis = 0; axis < 3; ++axis)
    for (double side : {-0.5, 1.5})
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          auto at = [&](int a, int b) {
            Vec3 p;
            p[axis] = side;
            p[(axis + 1) % 3] = -0.5 + 2.0 * a / k;
            p[(axis + 2) % 3] = -0.5 + 2.0 * b / k;
            return p;
          };
          t.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
          t.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
        }
  return t;
}

}  // namespace

TEST_CASE("BVH first hits are CGAL's, ray for ray, in clutter inside a closed box") {
  std::mt19937_64 rng(20261203);
  const Triangles triangles = clutter(3000, 0.05, rng);
  const TriangleBvh bvh(triangles);
  const Reference cgal(triangles);
  CHECK(bvh.depth() <= TriangleBvh::kMaxDepth);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int hits = 0, mismatched = 0;
  const int rays = 20000;
  for (int k = 0; k < rays; ++k) {
    const Vec3 o(u(rng), u(rng), u(rng));
    const Vec3 d = randomDirection(rng);
    const auto ref = cgal.firstHit(o, d);
    const TriangleBvh::Hit hit = bvh.firstHit(o, d);
    REQUIRE(ref.has_value());  // inside a closed box every ray hits something
    ++hits;
    // The same triangle, or (a ray through a shared edge) the same distance to 1e-12 m.
    // Distances agree to 1e-12 relative or 1e-13 m: CGAL measures from the hit point it
    // constructs, rounded to ~1e-16 m a coordinate.
    if (hit.triangle != ref->first && !(std::abs(hit.t - ref->second) <= 1e-12)) ++mismatched;
    CHECK(hit.t == Approx(ref->second).epsilon(1e-12).margin(1e-13));
    // The side met, from the sign of Möller–Trumbore's determinant, is the one the triangle's
    // normal (v1 − v0) × (v2 − v0) gives.
    const auto& v = triangles[static_cast<size_t>(hit.triangle)];
    CHECK(hit.front == ((v[1] - v[0]).cross(v[2] - v[0]).dot(d) < 0.0));
    // anyHit: true over the whole ray, false short of the first hit.
    CHECK(bvh.anyHit(o, d));
    CHECK_FALSE(bvh.anyHit(o, d, -1, hit.t * (1.0 - 1e-9)));
    // Skipping the first triangle gives CGAL's next one (none when it was the box's wall).
    const auto ref_next = cgal.firstHit(o, d, ref->first);
    const TriangleBvh::Hit next = bvh.firstHit(o, d, ref->first);
    REQUIRE(ref_next.has_value() == (next.triangle >= 0));
    if (ref_next) CHECK(next.t == Approx(ref_next->second).epsilon(1e-12).margin(1e-13));
  }
  CHECK(hits == rays);
  CHECK(mismatched == 0);
}

TEST_CASE("BVH: rays from outside, axis-parallel rays along box faces and through shared edges") {
  std::mt19937_64 rng(7);
  const Triangles triangles = clutter(500, 0.1, rng);
  const TriangleBvh bvh(triangles);
  const Reference cgal(triangles);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  int compared = 0;
  for (int k = 0; k < 5000; ++k) {  // from outside: hits and misses alike
    const Vec3 o(u(rng), u(rng), u(rng));
    const Vec3 d = randomDirection(rng);
    const auto ref = cgal.firstHit(o, d);
    const TriangleBvh::Hit hit = bvh.firstHit(o, d);
    REQUIRE(ref.has_value() == (hit.triangle >= 0));
    if (ref) CHECK(hit.t == Approx(ref->second).epsilon(1e-12).margin(1e-13));
    ++compared;
  }
  // Axis-parallel rays (zero direction components: the slab test's 0·∞ case) from outside
  // the box, on the planes of its grid lines, so the ray runs along box faces and meets the
  // near wall exactly on a shared edge or corner: a hit at 0.5 m every time.
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) {
        Vec3 o, d = Vec3::Zero();
        o[axis] = -1.0;
        o[(axis + 1) % 3] = -0.5 + 2.0 * i / 8;
        o[(axis + 2) % 3] = -0.5 + 2.0 * j / 8;
        d[axis] = 1.0;
        const bool on_rim = i == 0 || i == 8 || j == 0 || j == 8;
        const TriangleBvh::Hit hit = bvh.firstHit(o, d);
        if (on_rim) continue;  // the ray lies in a side wall's plane: grazing, measure zero
        REQUIRE(hit.triangle >= 0);
        const auto ref = cgal.firstHit(o, d);
        REQUIRE(ref.has_value());
        CHECK(hit.t == Approx(ref->second).epsilon(1e-12).margin(1e-13));
        CHECK(hit.t == Approx(0.5).epsilon(1e-15));
        ++compared;
      }
  CHECK(compared == 5000 + 3 * 49);
}

TEST_CASE("BVH on degenerate input: none, one, a thousand identical triangles, sizes 1e-6 to 1e3 m") {
  const TriangleBvh empty(Triangles{});
  CHECK(empty.firstHit(Vec3::Zero(), Vec3::UnitZ()).triangle == -1);
  CHECK_FALSE(empty.anyHit(Vec3::Zero(), Vec3::UnitZ()));

  const Triangles one{{Vec3(-1, -1, 1), Vec3(1, -1, 1), Vec3(0, 1, 1)}};
  const TriangleBvh single(one);
  CHECK(single.firstHit(Vec3::Zero(), Vec3::UnitZ()).t == Approx(1.0));
  CHECK(single.firstHit(Vec3::Zero(), Vec3::UnitZ(), 0).triangle == -1);  // skipped
  CHECK(single.firstHit(Vec3::Zero(), -Vec3::UnitZ()).triangle == -1);

  // All centres equal: no SAH split exists; the count-median split keeps the depth bounded.
  const Triangles same(1000, one[0]);
  const TriangleBvh stacked(same);
  CHECK(stacked.depth() <= TriangleBvh::kMaxDepth);
  CHECK(stacked.firstHit(Vec3::Zero(), Vec3::UnitZ()).t == Approx(1.0));

  // A micrometre triangle beside a kilometre one: each hit where it is.
  const Triangles mixed{{Vec3(0, 0, 2), Vec3(1e-6, 0, 2), Vec3(0, 1e-6, 2)},
                        {Vec3(-500, -500, 3), Vec3(500, -500, 3), Vec3(0, 500, 3)}};
  const TriangleBvh scales(mixed);
  const TriangleBvh::Hit tiny = scales.firstHit(Vec3(2.5e-7, 2.5e-7, 0), Vec3::UnitZ());
  CHECK(tiny.triangle == 0);
  CHECK(tiny.t == Approx(2.0));
  CHECK(scales.firstHit(Vec3(2e-6, 2e-6, 0), Vec3::UnitZ()).triangle == 1);
}
