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

// Four doubles, as GCC's vector extension: AVX where the machine has it, SSE pairs where not.
// (Without AVX, GCC notes that passing them changes the ABI: these helpers are internal and
// inlined, so no other unit sees them.)
#pragma GCC diagnostic ignored "-Wpsabi"
using Lanes = double __attribute__((vector_size(32)));
using LaneMask = long long __attribute__((vector_size(32)));

Lanes lanes(double x) { return Lanes{x, x, x, x}; }
Lanes lanesOf(const double* p) {
  Lanes v;
  __builtin_memcpy(&v, p, sizeof v);
  return v;
}
// Lane k's mask as bit k.
int bitsOf(const LaneMask& m) { return static_cast<int>((m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8)); }
Lanes lanesMin(const Lanes& a, const Lanes& b) { return a < b ? a : b; }
Lanes lanesMax(const Lanes& a, const Lanes& b) { return a > b ? a : b; }

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

struct TriangleBvh::BuildNode {  ///< a node of the binary build
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  ///< box, m
  std::int32_t next = 0;   ///< leaf: first triangle; inner: left child (right = left + 1)
  std::int32_t count = 0;  ///< triangles in a leaf, 0 for an inner node
};

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
  std::vector<BuildNode> nodes;
  nodes.reserve(2 * static_cast<size_t>(n));
  nodes.push_back({});
  std::vector<Range> work{{0, 0, n, 0}};
  while (!work.empty()) {
    const Range r = work.back();
    work.pop_back();
    depth_ = std::max(depth_, r.depth);
    const auto first = order.begin() + r.first, last = first + r.count;
    Box box, centres;
    for (auto it = first; it != last; ++it) box.grow(in.boxOf(*it)), centres.grow(in.centre[static_cast<size_t>(*it)]);
    BuildNode& node = nodes[static_cast<size_t>(r.node)];
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
    const int left = static_cast<int>(nodes.size()), mid = static_cast<int>(middle - order.begin());
    node.next = left, node.count = 0;  // `node` is not used after the push below
    nodes.push_back({});
    nodes.push_back({});
    work.push_back({left, r.first, mid - r.first, r.depth + 1});
    work.push_back({left + 1, mid, r.first + r.count - mid, r.depth + 1});
  }
  nodes_.reserve(nodes.size() / 2 + 1);
  collapse(nodes, 0);
  triangles_.reserve(static_cast<size_t>(n));
  for (const int i : order) {
    const auto& v = triangles[static_cast<size_t>(i)];
    triangles_.push_back({v[0], v[1] - v[0], v[2] - v[0], i});
  }
}

// The 4-wide node of binary node `from` and below (returns its index): the node's children,
// each inner one replaced by its own two children, largest box first, while fewer than four.
// A leaf root becomes a node with one child.
int TriangleBvh::collapse(const std::vector<BuildNode>& binary, int from) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back({});
  std::array<int, 4> kids{from, -1, -1, -1};
  int count = 1;
  auto area = [&](int k) {
    const Vec3 e = binary[static_cast<size_t>(k)].hi - binary[static_cast<size_t>(k)].lo;
    return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
  };
  for (;;) {
    int open = -1;  // the inner kid with the largest box
    for (int k = 0; k < count; ++k)
      if (binary[static_cast<size_t>(kids[k])].count == 0 && (open < 0 || area(kids[k]) > area(kids[open]))) open = k;
    if (open < 0 || count + 1 > 4) break;
    const int left = binary[static_cast<size_t>(kids[open])].next;
    kids[open] = left, kids[count++] = left + 1;
  }
  Node node;
  for (int k = 0; k < 4; ++k) {
    for (int a = 0; a < 3; ++a) node.lo[a][k] = node.hi[a][k] = 0.0;
    node.child[k] = 0, node.count[k] = -1;
    if (k >= count) continue;
    const BuildNode& b = binary[static_cast<size_t>(kids[k])];
    for (int a = 0; a < 3; ++a) node.lo[a][k] = b.lo[a], node.hi[a][k] = b.hi[a];
    node.count[k] = b.count;
    node.child[k] = b.count > 0 ? b.next : collapse(binary, kids[k]);
    (b.count > 0 ? node.leaf_bits : node.inner_bits) |= 1 << k;
  }
  nodes_[static_cast<size_t>(index)] = node;
  return index;
}

// Möller & Trumbore (1997) on a leaf's triangles, edges closed (u, v ≥ 0, u + v ≤ 1):
// whether one of them beats `best`, which then holds the nearest.
[[gnu::always_inline]] inline bool TriangleBvh::testLeaf(int first, int count, const Vec3& origin, const Vec3& dir,
                                                         int skip, Hit& best) const {
  bool found = false;
  for (int k = first; k < first + count; ++k) {
    const Triangle& tri = triangles_[static_cast<size_t>(k)];
    if (tri.id == skip) continue;
    const Vec3 p = dir.cross(tri.e2);
    const double det = tri.e1.dot(p);
    if (det == 0.0) continue;  // the ray lies in the triangle's plane
    // The barycentric tests on the numerators, scaled by the sign of det: no division
    // until a triangle is hit.
    const double sign = det > 0.0 ? 1.0 : -1.0, scale = sign * det;
    const Vec3 s = origin - tri.v0;
    const double u = sign * s.dot(p);
    if (!(u >= 0.0 && u <= scale)) continue;
    const Vec3 q = s.cross(tri.e1);
    const double v = sign * dir.dot(q);
    if (!(v >= 0.0 && u + v <= scale)) continue;
    const double t = tri.e2.dot(q) / det;
    // det = e1 · (dir × e2) = −dir · (e1 × e2): positive when the ray meets the front.
    if (t > 0.0 && t < best.t) best = {tri.id, t, det > 0.0}, found = true;
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
  const Lanes ox = lanes(origin.x()), oy = lanes(origin.y()), oz = lanes(origin.z());
  const Lanes ix = lanes(inv.x()), iy = lanes(inv.y()), iz = lanes(inv.z());
  // Node indices, uninitialised (a zeroed array costs a third of the rate, measured); each
  // level pushes at most 3 more than it pops.
  std::int32_t stack[3 * kMaxDepth + 4];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const std::int32_t entry = stack[--top];
    const Node& node = nodes_[static_cast<size_t>(entry)];
    // Slab test (Kay & Kajiya) of the four boxes at once, clipped to [0, best.t].
    const Lanes ax = (lanesOf(node.lo[0]) - ox) * ix, bx = (lanesOf(node.hi[0]) - ox) * ix;
    const Lanes ay = (lanesOf(node.lo[1]) - oy) * iy, by = (lanesOf(node.hi[1]) - oy) * iy;
    const Lanes az = (lanesOf(node.lo[2]) - oz) * iz, bz = (lanesOf(node.hi[2]) - oz) * iz;
    const Lanes t_near = lanesMax(lanesMax(lanesMin(ax, bx), lanesMin(ay, by)), lanesMax(lanesMin(az, bz), lanes(0.0)));
    const Lanes t_far = lanesMin(lanesMin(lanesMax(ax, bx), lanesMax(ay, by)), lanesMin(lanesMax(az, bz), lanes(best.t)));
    const int open = bitsOf(t_near <= t_far);
    // Open leaves are tested at once (a hit shortens the ray for the rest), then the open
    // inner children still nearer than the best hit go on the stack, the nearest last
    // (opened first): one without a sort, more by an insertion sort of at most four.
    for (int bits = open & node.leaf_bits; bits != 0; bits &= bits - 1) {
      const int k = __builtin_ctz(static_cast<unsigned>(bits));
      if (testLeaf(node.child[k], node.count[k], origin, dir, skip, best) && kAny) return best;
    }
    int inner = open & node.inner_bits & bitsOf(t_near <= lanes(best.t));
    if (inner == 0) continue;
    if ((inner & (inner - 1)) == 0) {
      stack[top++] = node.child[__builtin_ctz(static_cast<unsigned>(inner))];
      continue;
    }
    double key[4];
    std::int32_t what[4];
    int found = 0;
    for (; inner != 0; inner &= inner - 1) {
      const int k = __builtin_ctz(static_cast<unsigned>(inner));
      int at = found++;
      for (; at > 0 && key[at - 1] < t_near[k]; --at) key[at] = key[at - 1], what[at] = what[at - 1];
      key[at] = t_near[k], what[at] = node.child[k];
    }
    for (int k = 0; k < found; ++k) stack[top++] = what[k];
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
