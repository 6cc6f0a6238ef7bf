#include "geometry/exact/occluded_factor.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace radnet::geometry {
namespace {

// Dunavant (1985) degree-5 rule on a triangle: barycentric points and weights (sum 1).
struct QuadPoint {
  double l0, l1, l2, w;
};
const std::array<QuadPoint, 7> kRule = {{
    {1.0 / 3, 1.0 / 3, 1.0 / 3, 0.225},
    {0.059715871789770, 0.470142064105115, 0.470142064105115, 0.132394152788506},
    {0.470142064105115, 0.059715871789770, 0.470142064105115, 0.132394152788506},
    {0.470142064105115, 0.470142064105115, 0.059715871789770, 0.132394152788506},
    {0.797426985353087, 0.101286507323456, 0.101286507323456, 0.125939180544827},
    {0.101286507323456, 0.797426985353087, 0.101286507323456, 0.125939180544827},
    {0.101286507323456, 0.101286507323456, 0.797426985353087, 0.125939180544827},
}};

struct Tri {
  Vec3 a, b, c;
  double area() const { return 0.5 * (b - a).cross(c - a).norm(); }
};

// The half-spaces whose intersection is a blocker's shadow seen from a point: inside
// every plane through the point and an edge, and beyond the blocker's own plane.
// Stored as "lit" sides: m·x ≥ c is outside the shadow.
struct ShadowPlanes {
  std::vector<Vec3> m;
  std::vector<double> c;
  int count = 0;
};

bool shadowOf(const Vec3& p, double dp, const Occluder& b, ShadowPlanes& s) {
  const size_t m = b.polygon.size();
  s.m.resize(m + 1);
  s.c.resize(m + 1);
  s.count = 0;
  const Vec3 to_centre = b.centre - p;
  for (size_t k = 0; k < m; ++k) {
    Vec3 n = (b.polygon[k] - p).cross(b.polygon[(k + 1) % m] - p);
    if (n.dot(to_centre) > 0) n = -n;
    s.m[static_cast<size_t>(s.count)] = n;
    s.c[static_cast<size_t>(s.count++)] = n.dot(p);
  }
  const double sign = dp > 0 ? 1.0 : -1.0;
  s.m[static_cast<size_t>(s.count)] = sign * b.normal;
  s.c[static_cast<size_t>(s.count++)] = sign * b.offset;
  return true;
}

bool litByOnePlane(const ShadowPlanes& s, const Loop& piece) {
  for (int k = 0; k < s.count; ++k) {
    const Vec3& m = s.m[static_cast<size_t>(k)];
    const double c = s.c[static_cast<size_t>(k)];
    if (std::all_of(piece.begin(), piece.end(), [&](const Vec3& v) { return m.dot(v) >= c; })) return true;
  }
  return false;
}

void cutShadow(const ShadowPlanes& s, std::vector<Loop>& pieces, std::vector<Loop>& scratch) {
  scratch.clear();
  thread_local Loop lit, dark;
  for (Loop& piece : pieces) {
    if (litByOnePlane(s, piece)) {  // the shadow misses this piece: keep it whole
      scratch.push_back(std::move(piece));
      continue;
    }
    Loop current = std::move(piece);
    for (int k = 0; k < s.count && !current.empty(); ++k) {
      splitByPlane(current, s.m[static_cast<size_t>(k)], s.c[static_cast<size_t>(k)], lit, dark);
      if (!lit.empty()) scratch.push_back(lit);
      current.swap(dark);
    }
  }
  pieces.swap(scratch);
}

// Global adaptive quadrature over the emitter's triangles: every leaf carries its own
// rule (coarse) and the sum over its four children (fine), |fine − coarse| its error
// estimate; the leaf of largest estimate is split until the summed estimate meets the
// target. A recursion handing each child a quarter of its parent's target never meets it
// along a shadow's edge (there the error halves, not quarters, per level): it ran to the
// depth limit on every pair of two coaxial cylinders, minutes on 352 pairs. Worst first,
// the work goes where the error is and stops at a bounded count of evaluations.
class EmitterQuadrature {
 public:
  explicit EmitterQuadrature(const OccludedPair& pair) : pair_(pair) {}

  // A leaf of the triangle `t` whose own rule gave `own` (its parent computed it).
  void add(const Tri& t, int depth, double own) {
    Leaf leaf{t, depth, {}, own, 0.0};  // value = own until the children are summed
    const std::array<Tri, 4> kids = children(t);
    double fine = 0.0;
    for (size_t k = 0; k < 4; ++k) fine += leaf.kid_values[k] = rule(kids[k]);
    leaf.error = std::abs(fine - leaf.value);
    leaf.value = fine;  // the leaf's value from here on: the finer of the two
    error_ += leaf.error;
    leaves_.push_back(leaf);
    std::push_heap(leaves_.begin(), leaves_.end(), byError);
  }

  // Split the worst leaves until the summed estimate meets `tol` or the evaluations reach
  // `max_evaluations`; a leaf at max_depth is set aside as it is.
  FactorEstimate refine(double tol, int max_depth, long long max_evaluations) {
    while (!leaves_.empty() && error_ > tol && evaluations < max_evaluations) {
      std::pop_heap(leaves_.begin(), leaves_.end(), byError);
      const Leaf worst = leaves_.back();
      leaves_.pop_back();
      if (worst.depth >= max_depth) {
        finished_.push_back(worst);
        continue;
      }
      error_ -= worst.error;
      const std::array<Tri, 4> kids = children(worst.tri);
      for (size_t k = 0; k < 4; ++k) add(kids[k], worst.depth + 1, worst.kid_values[k]);
    }
    // The running sums drift by rounding over many updates: add the leaves afresh.
    FactorEstimate out;
    for (const std::vector<Leaf>* list : {&leaves_, &finished_})
      for (const Leaf& leaf : *list) {
        out.value += leaf.value;
        out.error += leaf.error;
      }
    out.evaluations = evaluations;
    return out;
  }
  double rule(const Tri& t) {
    const double area = t.area();
    double acc = 0.0;
    for (const auto& q : kRule) acc += q.w * visibleFactor(q.l0 * t.a + q.l1 * t.b + q.l2 * t.c, pair_);
    evaluations += static_cast<long long>(kRule.size());
    return acc * area;
  }
  long long evaluations = 0;

 private:
  struct Leaf {
    Tri tri;
    int depth;
    std::array<double, 4> kid_values;
    double value, error;
  };
  static bool byError(const Leaf& a, const Leaf& b) { return a.error < b.error; }
  static std::array<Tri, 4> children(const Tri& t) {
    const Vec3 ab = 0.5 * (t.a + t.b), bc = 0.5 * (t.b + t.c), ca = 0.5 * (t.c + t.a);
    return {{{t.a, ab, ca}, {ab, t.b, bc}, {ca, bc, t.c}, {ab, bc, ca}}};
  }

  const OccludedPair& pair_;
  std::vector<Leaf> leaves_;    // a max-heap on error
  std::vector<Leaf> finished_;  // at max_depth
  double error_ = 0.0;
};

// The emitter's pieces split along the lines where a blocker stands on it or passes
// through it: across such a line the view jumps (a wall on a plate hides the far side from the plate outside it),
// and a quadrature rule must not straddle the jump.
std::vector<Loop> emitterPieces(const OccludedPair& pair) {
  std::vector<Loop> pieces = *pair.emitter;
  if (pieces.empty()) return pieces;
  const Vec3& n = pair.emitter_normal;
  const double offset = n.dot(pieces[0][0]);
  std::vector<Loop> next;
  Loop a, b;
  for (const Occluder* blocker : pair.blockers) {
    const double scale = (blocker->hi - blocker->lo).norm();
    // Standing on the emitter's plane, or passing through it.
    double lowest = 1e300, highest = -1e300;
    for (const Vec3& v : blocker->polygon) {
      lowest = std::min(lowest, n.dot(v) - offset);
      highest = std::max(highest, n.dot(v) - offset);
    }
    const bool touches = lowest <= 1e-9 * scale && highest >= -1e-9 * scale;
    if (!touches || std::abs(std::abs(blocker->normal.dot(n)) - 1.0) < 1e-12) continue;  // parallel: no line
    next.clear();
    for (const Loop& piece : pieces) {
      splitByPlane(piece, blocker->normal, blocker->offset, a, b);
      if (!a.empty()) next.push_back(a);
      if (!b.empty()) next.push_back(b);
    }
    pieces.swap(next);
  }
  return pieces;
}

}  // namespace

double visibleFactor(const Vec3& point, const OccludedPair& pair) {
  thread_local std::vector<Loop> pieces, scratch;
  pieces.assign(pair.receiver->begin(), pair.receiver->end());
  thread_local ShadowPlanes planes;
  for (size_t k = 0; k < pair.blockers.size() && !pieces.empty(); ++k) {
    const Occluder& b = *pair.blockers[k];
    const double dp = b.normal.dot(point) - b.offset;
    // In the blocker's plane, or on the same side as the whole receiver: no shadow.
    if (std::abs(dp) <= 1e-12 * (b.hi - b.lo).norm()) continue;
    const int side = pair.receiver_side.empty() ? 0 : pair.receiver_side[k];
    if ((side > 0 && dp > 0) || (side < 0 && dp < 0)) continue;
    shadowOf(point, dp, b, planes);
    cutShadow(planes, pieces, scratch);
  }
  double f = 0.0;
  for (const Loop& piece : pieces) f += pointToConvexPolygon(point, pair.emitter_normal, piece);
  return f;
}

FactorEstimate occludedExchangeArea(OccludedPair& pair, double tolerance, int max_depth) {
  FactorEstimate out;
  pair.receiver_side.clear();
  for (const Occluder* b : pair.blockers) {
    bool front = true, back = true;
    for (const Loop& piece : *pair.receiver)
      for (const Vec3& v : piece) {
        const double d = b->normal.dot(v) - b->offset;
        front = front && d >= 0;
        back = back && d <= 0;
      }
    pair.receiver_side.push_back(front ? +1 : (back ? -1 : 0));
  }
  std::vector<Tri> tris;
  double total = 0.0;
  for (const Loop& piece : emitterPieces(pair))
    for (size_t k = 1; k + 1 < piece.size(); ++k) {
      tris.push_back({piece[0], piece[k], piece[k + 1]});
      total += tris.back().area();
    }
  if (total <= 0) return out;
  EmitterQuadrature q(pair);
  for (const Tri& t : tris) q.add(t, 0, q.rule(t));
  return q.refine(tolerance, max_depth, kMaxOccludedEvaluations);
}

}  // namespace radnet::geometry
