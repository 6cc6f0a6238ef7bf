#include "geometry/rays/bvh.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace radnet::geometry {

namespace {

struct Box {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
  void grow(const Vec3& p) { lo = lo.cwiseMin(p), hi = hi.cwiseMax(p); }
  void grow(const Box& b) { lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi); }
  /// Half the surface area (the SAH only compares areas), 0 for an empty box.
  double halfArea() const {
    if (!(hi.x() >= lo.x())) return 0.0;
    const Vec3 e = hi - lo;
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  }
};

constexpr int kBins = 16;
constexpr int kSahDepth = 40;     // past it, count-median splits (depth ≤ 40 + 31 < kMaxDepth)
constexpr int kLeafSize = 4;      // a leaf at most this big past kSahDepth or with no SAH split
constexpr int kMaxLeafSize = 16;  // a leaf the SAH may keep
// SAH costs in units of one ray-triangle test: visiting an inner node (two box tests).
constexpr double kTraversalCost = 1.0;

struct Range {
  int node, first, count, depth;
};

int binOf(double c, double lo, double scale) {
  return std::clamp(static_cast<int>((c - lo) * scale), 0, kBins - 1);
}

// Slab test (Kay & Kajiya) on a ray whose inverse direction has no infinities (see trace):
// the entry parameter into [0, t_max], or false when the box is missed there.
[[gnu::always_inline]] inline bool enters(const Vec3& lo, const Vec3& hi, const Vec3& origin, const Vec3& inv, double t_max, double& t_near) {
  double t0 = 0.0, t1 = t_max;
  for (int a = 0; a < 3; ++a) {
    const double ta = (lo[a] - origin[a]) * inv[a];
    const double tb = (hi[a] - origin[a]) * inv[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  t_near = t0;
  return t0 <= t1;
}

}  // namespace

namespace {

// What the build reads of each triangle: its box and the box's centre (m).
struct BuildInput {
  std::vector<Box> box;
  std::vector<Vec3> centre;
  const Box& boxOf(int i) const { return box[static_cast<size_t>(i)]; }
  double centreOf(int i, int axis) const { return centre[static_cast<size_t>(i)][axis]; }
};

struct Split {
  int axis = -1;  ///< −1: no split cheaper than the leaf
  int bin = 0;    ///< the left side holds bins 0 … bin
};

// The binned SAH split of order[first, last) (Wald 2007): the cheapest plane between 16
// bins of the centres' bounds on each axis, if it costs less than `leaf_cost`.
Split bestSahSplit(const BuildInput& in, std::vector<int>::iterator first, std::vector<int>::iterator last,
                   const Box& box, const Box& centres, double leaf_cost) {
  Split best;
  const int total = static_cast<int>(last - first);
  double best_cost = leaf_cost;
  for (int a = 0; a < 3; ++a) {
    const double extent = centres.hi[a] - centres.lo[a];
    if (!(extent > 0.0)) continue;
    const double scale = kBins / extent;
    std::array<Box, kBins> bin_box;
    std::array<int, kBins> bin_count{};
    for (auto it = first; it != last; ++it) {
      const auto b = static_cast<size_t>(binOf(in.centreOf(*it, a), centres.lo[a], scale));
      ++bin_count[b];
      bin_box[b].grow(in.boxOf(*it));
    }
    std::array<double, kBins> right_cost{};  // area × count of bins b+1 … end
    Box acc;
    int count = 0;
    for (size_t b = kBins - 1; b > 0; --b) {
      acc.grow(bin_box[b]), count += bin_count[b];
      right_cost[b - 1] = acc.halfArea() * count;
    }
    acc = Box(), count = 0;
    for (size_t b = 0; b + 1 < kBins; ++b) {
      acc.grow(bin_box[b]), count += bin_count[b];
      if (count == 0 || count == total) continue;
      const double cost = kTraversalCost + (acc.halfArea() * count + right_cost[b]) / box.halfArea();
      if (cost < best_cost) best_cost = cost, best = {a, static_cast<int>(b)};
    }
  }
  return best;
}

// No SAH split (too deep, or all centres in one bin): halve the count along the centres'
// longest extent, which bounds the depth whatever the input. Returns the middle.
std::vector<int>::iterator medianSplit(const BuildInput& in, std::vector<int>::iterator first,
                                       std::vector<int>::iterator last, const Box& centres) {
  Eigen::Index longest = 0;
  (centres.hi - centres.lo).maxCoeff(&longest);
  const auto middle = first + (last - first) / 2;
  std::nth_element(first, middle, last,
                   [&](int i, int j) { return in.centreOf(i, longest) < in.centreOf(j, longest); });
  return middle;
}

}  // namespace

TriangleBvh::TriangleBvh(const std::vector<std::array<Vec3, 3>>& triangles) {
  const int n = static_cast<int>(triangles.size());
  if (n == 0) return;
  BuildInput in{std::vector<Box>(static_cast<size_t>(n)), std::vector<Vec3>(static_cast<size_t>(n))};
  for (size_t i = 0; i < static_cast<size_t>(n); ++i) {
    for (const Vec3& v : triangles[i]) in.box[i].grow(v);
    in.centre[i] = 0.5 * (in.box[i].lo + in.box[i].hi);
  }
  std::vector<int> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  nodes_.reserve(2 * static_cast<size_t>(n));
  nodes_.push_back({});
  std::vector<Range> work{{0, 0, n, 0}};
  while (!work.empty()) {
    const Range r = work.back();
    work.pop_back();
    depth_ = std::max(depth_, r.depth);
    const auto first = order.begin() + r.first, last = first + r.count;
    Box box, centres;
    for (auto it = first; it != last; ++it) box.grow(in.boxOf(*it)), centres.grow(in.centre[static_cast<size_t>(*it)]);
    Node& node = nodes_[static_cast<size_t>(r.node)];
    node.lo = box.lo, node.hi = box.hi;
    const Split split = r.count > 2 && r.depth < kSahDepth
                            ? bestSahSplit(in, first, last, box, centres, static_cast<double>(r.count))
                            : Split{};
    if (r.count <= 2 || (split.axis < 0 && r.count <= (r.depth < kSahDepth ? kMaxLeafSize : kLeafSize))) {
      node.next = r.first, node.count = r.count;
      continue;
    }
    auto middle = last;
    if (split.axis >= 0) {
      const double scale = kBins / (centres.hi[split.axis] - centres.lo[split.axis]);
      middle = std::partition(first, last, [&](int i) {
        return binOf(in.centreOf(i, split.axis), centres.lo[split.axis], scale) <= split.bin;
      });
    }
    if (middle == first || middle == last) middle = medianSplit(in, first, last, centres);
    const int left = static_cast<int>(nodes_.size()), mid = static_cast<int>(middle - order.begin());
    node.next = left, node.count = 0;  // `node` is not used after the push below
    nodes_.push_back({});
    nodes_.push_back({});
    work.push_back({left, r.first, mid - r.first, r.depth + 1});
    work.push_back({left + 1, mid, r.first + r.count - mid, r.depth + 1});
  }
  triangles_.reserve(static_cast<size_t>(n));
  for (const int i : order) {
    const auto& v = triangles[static_cast<size_t>(i)];
    triangles_.push_back({v[0], v[1] - v[0], v[2] - v[0], i});
  }
}

// Möller & Trumbore (1997) on a leaf's triangles, edges closed (u, v ≥ 0, u + v ≤ 1):
// whether one of them beats `best`, which then holds the nearest.
[[gnu::always_inline]] inline bool TriangleBvh::testLeaf(const Node& node, const Vec3& origin, const Vec3& dir,
                                                         int skip, Hit& best) const {
  bool found = false;
  for (int k = node.next; k < node.next + node.count; ++k) {
    const Triangle& tri = triangles_[static_cast<size_t>(k)];
    if (tri.id == skip) continue;
    const Vec3 p = dir.cross(tri.e2);
    const double det = tri.e1.dot(p);
    if (det == 0.0) continue;  // the ray lies in the triangle's plane
    const double inv_det = 1.0 / det;
    const Vec3 s = origin - tri.v0;
    const double u = s.dot(p) * inv_det;
    if (!(u >= 0.0 && u <= 1.0)) continue;
    const Vec3 q = s.cross(tri.e1);
    const double v = dir.dot(q) * inv_det;
    if (!(v >= 0.0 && u + v <= 1.0)) continue;
    const double t = tri.e2.dot(q) * inv_det;
    if (t > 0.0 && t < best.t) best = {tri.id, t}, found = true;
  }
  return found;
}

template <bool kAny>
TriangleBvh::Hit TriangleBvh::trace(const Vec3& origin, const Vec3& dir, int skip, double t_max) const {
  Hit best;
  best.t = t_max;
  if (nodes_.empty()) return Hit{};
  // A zero component's inverse is taken as ±1e300, not ±∞: 0·∞ (an origin on a box's face,
  // the ray parallel to it) would be NaN, while 0·1e300 = 0 keeps the face closed.
  Vec3 inv;
  for (int a = 0; a < 3; ++a) inv[a] = 1.0 / (dir[a] != 0.0 ? dir[a] : std::copysign(1e-300, dir[a]));
  // Node indices only, uninitialised: a zeroed std::array, or entry distances checked on
  // every pop, cost a third of the rate (measured).
  std::int32_t stack[kMaxDepth + 2];
  int top = 0;
  double t_near = 0.0;
  if (!enters(nodes_[0].lo, nodes_[0].hi, origin, inv, best.t, t_near)) return Hit{};
  stack[top++] = 0;
  while (top > 0) {
    const auto index = stack[--top];
    const Node& node = nodes_[static_cast<size_t>(index)];
    if (node.count > 0) {
      if (testLeaf(node, origin, dir, skip, best) && kAny) return best;
      continue;
    }
    const Node& a = nodes_[static_cast<size_t>(node.next)];
    const Node& b = nodes_[static_cast<size_t>(node.next + 1)];
    double ta = 0.0, tb = 0.0;
    const bool hit_a = enters(a.lo, a.hi, origin, inv, best.t, ta);
    const bool hit_b = enters(b.lo, b.hi, origin, inv, best.t, tb);
    // The nearer child goes on top, so it is opened first.
    if (hit_a && hit_b) {
      if (ta <= tb) {
        stack[top++] = node.next + 1;
        stack[top++] = node.next;
      } else {
        stack[top++] = node.next;
        stack[top++] = node.next + 1;
      }
    } else if (hit_a) {
      stack[top++] = node.next;
    } else if (hit_b) {
      stack[top++] = node.next + 1;
    }
  }
  if (best.triangle < 0) best.t = std::numeric_limits<double>::infinity();
  return best;
}

TriangleBvh::Hit TriangleBvh::firstHit(const Vec3& origin, const Vec3& dir, int skip, double t_max) const {
  return trace<false>(origin, dir, skip, t_max);
}

bool TriangleBvh::anyHit(const Vec3& origin, const Vec3& dir, int skip, double t_max) const {
  return trace<true>(origin, dir, skip, t_max).triangle >= 0;
}

}  // namespace radnet::geometry
