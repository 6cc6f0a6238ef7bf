#pragma once
// A bounding volume hierarchy over triangles, built by the surface area heuristic, for the
// first-hit and any-hit ray queries behind every view factor and load.
//
// Why not CGAL's AABB tree (the caster's first tree): CGAL splits every node at the median
// count along its longest axis. On CAD and FE assemblies, where small triangles crowd around
// holes and fillets and large ones span the plates between, a count median puts big and
// small together and the boxes overlap; its ray traversal also keeps a heap. Measured on a
// real six-part 1U frame (37,706 triangles): 296 box tests a ray with CGAL against 35 here,
// 13× the rays a second in `radnet run` (docs/geometry.md). CGAL's tree stays the reference
// the tests check this one against.
//
// Build: binned SAH (Wald 2007, "On fast construction of SAH-based bounding volume
// hierarchies"): 16 bins of the centroid bounds per axis, a split taken where it costs less
// than a leaf; past depth 40 nodes split at the count median, so depth stays below 104.
// Traversal: a stack, the nearer child first, a child whose box begins beyond the best hit
// so far left shut; the ray-box test is the slab test, the ray-triangle test Möller–Trumbore
// (1997) with closed edges: a ray exactly through a shared edge meets both triangles. The test is not watertight under
// rounding (Woop et al. 2013): a gap of about 1e-16 of a triangle's size can open along an
// edge, some 1e-14 of the rays, far below any Monte Carlo error bar.
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

  static constexpr int kMaxDepth = 104;  ///< build guarantee; the traversal stack holds this many

 private:
  struct Node {  ///< siblings are adjacent, so the two boxes a ray tests share 112 bytes
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< box, m
    std::int32_t next = 0;   ///< leaf: first triangle; inner: left child (right = left + 1)
    std::int32_t count = 0;  ///< triangles in a leaf, 0 for an inner node
  };
  struct Triangle {        ///< in leaf order, stored for Möller–Trumbore
    Vec3 v0, e1, e2;
    int id;
  };
  bool testLeaf(const Node& node, const Vec3& origin, const Vec3& dir, int skip, Hit& best) const;
  template <bool kAny>
  Hit trace(const Vec3& origin, const Vec3& dir, int skip, double t_max) const;

  std::vector<Node> nodes_;
  std::vector<Triangle> triangles_;
  int depth_ = 0;
};

}  // namespace radnet::geometry
