#include "geometry/exact/shaft.hpp"

#include <algorithm>
#include <numeric>

namespace radnet::geometry {
namespace {

constexpr int kLeafSize = 4;
// Hull planes cost |edges of P| × |vertices of Q| tests each way; beyond this many
// combinations the cheaper tests alone decide (more candidates, never a wrong answer).
constexpr size_t kMaxHullCombinations = 256;

bool overlaps(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
  return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
}

struct HalfSpace {
  Vec3 m;
  double c;  // inside: m·x ≤ c
};

// Whether all points lie at m·x − c ≥ −tol (none strictly inside).
bool allOutside(const Loop& points, const Vec3& m, double c, double tol) {
  for (const Vec3& v : points)
    if (m.dot(v) - c < -tol) return false;
  return true;
}

void collect(const std::vector<Loop>& pieces, std::vector<Vec3>& points) {
  for (const Loop& l : pieces) points.insert(points.end(), l.begin(), l.end());
}

// Planes through an edge of `a` and a vertex of `b` with every point on one side.
void hullPlanes(const std::vector<Loop>& a, const std::vector<Vec3>& b_points, const std::vector<Vec3>& all,
                double tol, std::vector<HalfSpace>& out) {
  for (const Loop& loop : a)
    for (size_t k = 0; k < loop.size(); ++k) {
      const Vec3& p0 = loop[k];
      const Vec3 e = loop[(k + 1) % loop.size()] - p0;
      for (const Vec3& q : b_points) {
        Vec3 m = e.cross(q - p0);
        const double len = m.norm();
        if (len <= 1e-300) continue;
        m /= len;
        const double c = m.dot(p0);
        bool below = true, above = true;
        for (const Vec3& x : all) {
          const double d = m.dot(x) - c;
          below = below && d <= tol;
          above = above && d >= -tol;
        }
        if (below) out.push_back({m, c});
        if (above && !below) out.push_back({-m, -c});
      }
    }
}

}  // namespace

OccluderIndex::OccluderIndex(std::vector<Occluder> occluders) : occluders_(std::move(occluders)) {
  order_.resize(occluders_.size());
  std::iota(order_.begin(), order_.end(), 0);
  if (!occluders_.empty()) build(0, static_cast<int>(order_.size()));
}

int OccluderIndex::build(int first, int count) {
  BoxNode node;
  node.lo = Vec3::Constant(1e300);
  node.hi = Vec3::Constant(-1e300);
  for (int k = first; k < first + count; ++k) {
    const Occluder& o = occluders_[static_cast<size_t>(order_[static_cast<size_t>(k)])];
    node.lo = node.lo.cwiseMin(o.lo);
    node.hi = node.hi.cwiseMax(o.hi);
  }
  const int id = static_cast<int>(nodes_.size());
  nodes_.push_back(node);
  if (count <= kLeafSize) {
    nodes_[static_cast<size_t>(id)].first = first;
    nodes_[static_cast<size_t>(id)].count = count;
    return id;
  }
  int axis = 0;
  (node.hi - node.lo).maxCoeff(&axis);
  const auto begin = order_.begin() + first, mid = begin + count / 2, end = begin + count;
  std::nth_element(begin, mid, end, [&](int a, int b) {
    const Occluder &oa = occluders_[static_cast<size_t>(a)], &ob = occluders_[static_cast<size_t>(b)];
    return oa.lo[axis] + oa.hi[axis] < ob.lo[axis] + ob.hi[axis];
  });
  const int left = build(first, count / 2);
  const int right = build(first + count / 2, count - count / 2);
  nodes_[static_cast<size_t>(id)].left = left;
  nodes_[static_cast<size_t>(id)].right = right;
  return id;
}

void OccluderIndex::query(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const {
  if (nodes_.empty()) return;
  int stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const BoxNode& node = nodes_[static_cast<size_t>(stack[--top])];
    if (!overlaps(node.lo, node.hi, lo, hi)) continue;
    if (node.left < 0) {
      for (int k = node.first; k < node.first + node.count; ++k) {
        const int o = order_[static_cast<size_t>(k)];
        const Occluder& occ = occluders_[static_cast<size_t>(o)];
        if (overlaps(occ.lo, occ.hi, lo, hi)) out.push_back(o);
      }
      continue;
    }
    stack[top++] = node.left;
    stack[top++] = node.right;
  }
}

void pairBlockers(const OccluderIndex& index, const Patch& p, const std::vector<Loop>& p_pieces, const Patch& q,
                  const std::vector<Loop>& q_pieces, double tol, std::vector<int>& candidates,
                  std::vector<int>& blockers) {
  blockers.clear();
  candidates.clear();
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  std::vector<Vec3> pp, qq;
  collect(p_pieces, pp);
  collect(q_pieces, qq);
  for (const Vec3& v : pp) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  for (const Vec3& v : qq) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  index.query(lo - Vec3::Constant(tol), hi + Vec3::Constant(tol), candidates);
  if (candidates.empty()) return;
  std::vector<Vec3> all = pp;
  all.insert(all.end(), qq.begin(), qq.end());
  // The plane tests first: the hull's planes cost |P| |Q| (|P| + |Q|) products, and where
  // every candidate lies behind a patch or beside both (a cluster pair of a flat bus face
  // and a wing: most of them), they are not needed.
  for (int id : candidates) {
    const Occluder& o = index.occluders()[static_cast<size_t>(id)];
    // Behind or in either patch's plane: no segment between them gets there.
    if (allOutside(o.polygon, -p.region.normal, -p.offset, tol)) continue;
    if (allOutside(o.polygon, -q.region.normal, -q.offset, tol)) continue;
    // P and Q on one side of the occluder's plane: no segment crosses it.
    if (allOutside(all, o.normal, o.offset, tol) || allOutside(all, -o.normal, -o.offset, tol)) continue;
    blockers.push_back(id);
  }
  if (blockers.empty() || pp.size() * qq.size() > kMaxHullCombinations) return;
  std::vector<HalfSpace> hull;
  hullPlanes(p_pieces, qq, all, tol, hull);
  hullPlanes(q_pieces, pp, all, tol, hull);
  const auto outside_hull = [&](int id) {
    for (const HalfSpace& h : hull)
      if (allOutside(index.occluders()[static_cast<size_t>(id)].polygon, h.m, h.c, tol)) return true;
    return false;
  };
  blockers.erase(std::remove_if(blockers.begin(), blockers.end(), outside_hull), blockers.end());
}

namespace {

// Whether the segment a–b crosses the convex polygon strictly inside (by more than tol).
bool segmentThrough(const Occluder& o, const Vec3& a, const Vec3& b, double tol) {
  const double da = o.normal.dot(a) - o.offset, db = o.normal.dot(b) - o.offset;
  if (!((da > tol && db < -tol) || (da < -tol && db > tol))) return false;
  const Vec3 x = a + (da / (da - db)) * (b - a);
  const size_t m = o.polygon.size();
  for (size_t k = 0; k < m; ++k) {
    const Vec3 e = o.polygon[(k + 1) % m] - o.polygon[k];
    // Inside: to the left of every edge about the normal, by more than tol.
    const Vec3 inward = o.normal.cross(e);
    const double side = inward.dot(x - o.polygon[k]) / std::max(inward.norm(), 1e-300);
    if (side <= tol) return false;
  }
  return true;
}

}  // namespace

bool fullyOccludes(const Occluder& o, const std::vector<Loop>& p_pieces, const std::vector<Loop>& q_pieces,
                   double tol) {
  // The occluder's loop is counter-clockwise about its normal by construction; orient the
  // inside test the same way whichever way it turns.
  Occluder oriented = o;
  if (signedArea(o.polygon, o.normal) < 0) oriented.normal = -o.normal, oriented.offset = -o.offset;
  for (const Loop& pl : p_pieces)
    for (const Vec3& a : pl)
      for (const Loop& ql : q_pieces)
        for (const Vec3& b : ql)
          if (!segmentThrough(oriented, a, b, tol)) return false;
  return true;
}

}  // namespace radnet::geometry
