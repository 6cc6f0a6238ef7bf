#pragma once
// A bounding volume hierarchy over triangles, built by the surface area heuristic, for the
// first-hit and any-hit ray queries behind every view factor and load.
//
// Why not CGAL's AABB tree (the caster's first tree): CGAL splits every node at the median
// count along its longest axis. On CAD and FE assemblies, where small triangles crowd around
// holes and fillets and large ones span the plates between, a count median puts big and
// small together and the boxes overlap; its ray traversal also keeps a heap. Measured on a
// real six-part 1U frame (37,706 triangles): 296 box tests a ray with CGAL against 35 with
// the binary SAH tree, 13× the rays a second in `radnet run` (docs/geometry.md). CGAL's
// tree stays the reference the tests check this one against.
//
// Build: binned SAH (Wald 2007, "On fast construction of SAH-based bounding volume
// hierarchies"): 16 bins of the centroid bounds per axis, a split taken where it costs less
// than a leaf; past depth 40 nodes split at the count median, so depth stays below 104.
// The binary tree is then collapsed four-wide (each node's inner children replaced by their
// own, the largest box first, up to four): a node holds its four children's boxes side by
// side, and one SIMD slab test (GCC vector extensions: AVX where the machine has it) opens
// them all. Against the binary tree of one box a test, in one session: ×1.25 on the
// CubeSatSim frame's and the satellite's rays, ×1.5 on flat panels (bench_ray_caster).
// Tried and dropped: spatial splits (SBVH, Stich et al. 2009) left the frame's box visits
// at 15.5 against 15.8 for a 10× longer build; boxes in float (half the memory) let rays
// leaving a plane enter their neighbours' flat boxes, rounded outward: 40 % more visits,
// 3× the triangle tests.
//
// Traversal: a stack; the open leaves of a node are tested at once, its open inner children
// still nearer than the best hit are pushed the nearest last; the ray-box test is the slab
// test, the ray-triangle test Möller–Trumbore (1997) with closed edges, its barycentric tests
// on the numerators (one division, for a hit): a ray exactly through a shared edge meets both
// triangles. The test is not watertight under rounding (Woop et al. 2013): a gap of about
// 1e-16 of a triangle's size can open along an edge, some 1e-14 of the rays, far below any
// Monte Carlo error bar.
#include <Eigen/Core>
#include <Eigen/Geometry>  // cross products

#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace radnet::geometry {

using Vec3 = Eigen::Vector3d;  // as in scene.hpp

class TriangleBvh {
 public:
  struct Hit {
    int triangle = -1;                                    ///< index into the input, −1: none
    double t = std::numeric_limits<double>::infinity();  ///< ray parameter (m for a unit direction)
    bool front = false;  ///< the ray met the side (v1 − v0) × (v2 − v0) points to
  };

  explicit TriangleBvh(const std::vector<std::array<Vec3, 3>>& triangles);

  /// The nearest triangle hit at 0 < t < t_max, triangle `skip` ignored.
  Hit firstHit(const Vec3& origin, const Vec3& dir, int skip = -1,
               double t_max = std::numeric_limits<double>::infinity()) const;
  /// Whether any triangle but `skip` is hit at 0 < t < t_max (stops at the first one found).
  bool anyHit(const Vec3& origin, const Vec3& dir, int skip = -1,
              double t_max = std::numeric_limits<double>::infinity()) const;

  size_t nodeCount() const { return nodes_.size(); }
  int depth() const { return depth_; }

  static constexpr int kMaxDepth = 104;  ///< build guarantee; the traversal stack holds 3 entries a level

 private:
  /// Four children side by side, one SIMD slab test opens them all (a 4-wide hierarchy
  /// collapsed from the binary SAH build: half the depth, and the box tests without the
  /// branches of one box at a time).
  struct alignas(64) Node {
    double lo[3][4], hi[3][4];  ///< per axis, per child, m
    std::int32_t child[4];      ///< inner child: its node; leaf child: its first triangle
    std::int32_t count[4];      ///< leaf child: its triangles (> 0); inner: 0; no child: −1
    std::int32_t leaf_bits = 0, inner_bits = 0;  ///< bit k: child k is a leaf, an inner node
  };
  struct Triangle {        ///< in leaf order, stored for Möller–Trumbore
    Vec3 v0, e1, e2;
    int id;
  };
  struct BuildNode;
  int collapse(const std::vector<BuildNode>& binary, int from);
  bool testLeaf(int first, int count, const Vec3& origin, const Vec3& dir, int skip, Hit& best) const;
  template <bool kAny>
  Hit trace(const Vec3& origin, const Vec3& dir, int skip, double t_max) const;

  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;
  int depth_ = 0;
};

}  // namespace radnet::geometry
