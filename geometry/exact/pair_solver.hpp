#pragma once
// What the exact method's threads share (ExactScene: patches, occluders, clusters, point
// rules) and what each does with a pair of patches (PairSolver: cull, clip, find blockers,
// integrate), with the order pairs are visited in. Internal to geometry/exact/.
#include "geometry/exact/clusters.hpp"
#include "geometry/exact/occluded_factor.hpp"
#include "geometry/exact/pair_quadrature.hpp"
#include "geometry/exact/patches.hpp"
#include "geometry/exact/polygon_factor.hpp"
#include "geometry/exact/shaft.hpp"
#include "geometry/exact/view_factors.hpp"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace radnet::geometry {

// Free: in a free cluster pair (unoccluded and unclipped, known without classifying).
enum class PairKind { Culled, Hidden, Unoccluded, Occluded, Sampled, Free };

// What every thread reads: patches, occluders, their clusters and point rules, and each
// patch's share of its node's area.
struct ExactScene {
  // opt.node_pairs spares the clusters' classification the cluster pairs it leaves out whole.
  ExactScene(const Scene& scene, int threads, const ExactOptions& opt)
      : patches(buildPatches(scene)),
        index(buildOccluders(scene)),
        tol(1e-9 * std::max(scene.extent(), 1e-300)),
        rules(patches),
        clusters(patches, index, tol, threads, opt.node_pairs) {
    for (const Node& node : scene.nodes()) node_area.push_back(node.area_m2);
    for (const Patch& p : patches) {
      points.push_back(pointsOf(p));
      share.push_back(p.node >= 0 ? p.area_m2 / node_area[static_cast<size_t>(p.node)] : 1.0);
    }
  }
  // Marks the nodes of more than max_patches patches; returns them per node.
  std::vector<char> presample(size_t nodes, int max_patches) {
    std::vector<int> count(nodes, 0);
    for (const Patch& p : patches)
      if (p.node >= 0) ++count[static_cast<size_t>(p.node)];
    std::vector<char> rows(nodes, 0);
    for (size_t i = 0; i < nodes; ++i) rows[i] = max_patches >= 0 && count[i] > max_patches;
    markSampled(rows);
    return rows;
  }
  // Patches of sampled rows, and inactive sides (they have no row), are not integrated
  // against each other.
  void markSampled(const std::vector<char>& rows) {
    sampled.clear();
    for (const Patch& p : patches) sampled.push_back(p.node >= 0 ? rows[static_cast<size_t>(p.node)] : 1);
  }
  std::vector<Patch> patches;
  OccluderIndex index;
  double tol = 0.0;  // m: nearer a plane than this counts as on it
  PatchRules rules;
  PatchClusters clusters;
  std::vector<std::vector<Vec3>> points;
  std::vector<double> node_area, share;
  std::vector<char> sampled;  // per patch: its node's row is cast as rays from the start
};

// One thread's pair computations (its own scratch lists).
class PairSolver {
 public:
  PairSolver(const ExactScene& scene, const ExactOptions& opt) : s_(scene), opt_(opt) {}

  // Culls, clips and finds the blockers of the pair; integrate() then uses them.
  PairKind classify(size_t a, size_t b) {
    a_ = a;
    b_ = b;
    candidates_.clear();
    blockers_.clear();
    const Patch &p = s_.patches[a], &q = s_.patches[b];
    if (s_.sampled[a] && s_.sampled[b]) return PairKind::Culled;  // neither row is integrated
    if (allBehind(s_.points[b], p, s_.tol) || allBehind(s_.points[a], q, s_.tol)) return PairKind::Culled;
    clip_p_ = anyBehind(s_.points[a], q, s_.tol);
    clip_q_ = anyBehind(s_.points[b], p, s_.tol);
    // The patches' own pieces unless clipped: no copy on the common path.
    if (clip_p_) clipped_p_ = clippedPieces(p, q);
    if (clip_q_) clipped_q_ = clippedPieces(q, p);
    p_pieces_ = clip_p_ ? &clipped_p_ : &p.pieces;
    q_pieces_ = clip_q_ ? &clipped_q_ : &q.pieces;
    if (p_pieces_->empty() || q_pieces_->empty()) return PairKind::Culled;
    pairBlockers(s_.index, p, *p_pieces_, q, *q_pieces_, s_.tol, candidates_, blockers_);
    if (blockers_.empty()) return PairKind::Unoccluded;
    for (int id : blockers_)
      if (fullyOccludes(s_.index.occluders()[static_cast<size_t>(id)], *p_pieces_, *q_pieces_, s_.tol))
        return PairKind::Hidden;
    if (opt_.max_blockers >= 0 && static_cast<int>(blockers_.size()) > opt_.max_blockers) return PairKind::Sampled;
    return PairKind::Occluded;
  }
  // A pair of a free cluster pair: whole, unoccluded (no classification needed).
  void setFree(size_t a, size_t b) {
    a_ = a;
    b_ = b;
    clip_p_ = clip_q_ = false;
    p_pieces_ = &s_.patches[a].pieces;
    q_pieces_ = &s_.patches[b].pieces;
  }
  size_t blockers() const { return blockers_.size(); }
  size_t candidates() const { return candidates_.size(); }

  // Free and unclipped unoccluded pairs try the ladder of point rules first; the contour
  // integral takes what it leaves, and the occluded pairs their quadrature. The target is
  // the absolute one or relative_tolerance of the pair's value, whichever is larger.
  FactorEstimate integrate(PairKind kind) {
    const Patch &p = s_.patches[a_], &q = s_.patches[b_];
    // This pair's share of the target on F_ij and F_ji alike (see docs/geometry.md).
    const double area_i = p.node >= 0 ? s_.node_area[static_cast<size_t>(p.node)] : p.area_m2;
    const double area_j = q.node >= 0 ? s_.node_area[static_cast<size_t>(q.node)] : q.area_m2;
    const double tol = opt_.tolerance * s_.share[a_] * s_.share[b_] * std::min(area_i, area_j);
    by_quadrature = false;
    const bool whole = !clip_p_ && !clip_q_;
    long long evaluations = 0;
    double scale = 0.0;  // a value for the relative target (the ladder's best, else the centroids')
    if (kind == PairKind::Free || (kind == PairKind::Unoccluded && whole)) {
      const FactorEstimate est = s_.rules.exchangeArea(a_, b_, tol, opt_.relative_tolerance, by_quadrature);
      if (by_quadrature) return est;
      evaluations = est.evaluations;
      scale = est.value;
    } else if (whole) {
      scale = s_.rules.centroidValue(a_, b_);
    }
    const double target = std::max(tol, opt_.relative_tolerance * scale);
    FactorEstimate out;
    if (kind == PairKind::Free || kind == PairKind::Unoccluded) {
      const PlanarRegion pr = clip_p_ ? PlanarRegion{*p_pieces_, p.region.normal} : p.region;
      const PlanarRegion qr = clip_q_ ? PlanarRegion{*q_pieces_, q.region.normal} : q.region;
      out = polygonExchangeArea(pr, qr, target);
    } else {
      OccludedPair pair{p_pieces_, p.region.normal, q_pieces_, {}, {}};
      for (int id : blockers_) pair.blockers.push_back(&s_.index.occluders()[static_cast<size_t>(id)]);
      out = occludedExchangeArea(pair, target, opt_.max_depth);
    }
    out.evaluations += evaluations;
    return out;
  }
  bool by_quadrature = false;  ///< the last integrate() was settled by the ladder

 private:
  const ExactScene& s_;
  const ExactOptions& opt_;
  size_t a_ = 0, b_ = 0;
  bool clip_p_ = false, clip_q_ = false;
  std::vector<Loop> clipped_p_, clipped_q_;
  const std::vector<Loop>* p_pieces_ = nullptr;
  const std::vector<Loop>* q_pieces_ = nullptr;
  std::vector<int> candidates_, blockers_;
};

// Patches whose rows are integrated; a pair is visited from its exact side: for exact a,
// every b that is sampled or comes after a.
std::vector<int> exactPatches(const ExactScene& scene);

inline bool visitedFrom(const ExactScene& scene, int a, int b) {
  return b != a && (scene.sampled[static_cast<size_t>(b)] || b > a);
}

// Whether the caller's node-pair filter leaves the pair of patches a, b out.
inline bool filteredOut(const ExactScene& scene, const ExactOptions& opt, int a, int b) {
  if (!opt.node_pairs) return false;
  const int na = scene.patches[static_cast<size_t>(a)].node, nb = scene.patches[static_cast<size_t>(b)].node;
  return na >= 0 && nb >= 0 && !opt.node_pairs(na, nb);
}

// Calls visit(b, free) for every pair visited from `a`, cluster by cluster, until it
// returns false; pairs of culled cluster pairs are only counted. `free`: the pair lies in a
// free cluster pair (whole and unoccluded without further tests).
template <class Visit>
void forPairs(const ExactScene& scene, int a, std::int64_t& culled, Visit&& visit) {
  const auto ca = static_cast<size_t>(scene.clusters.clusterOf(static_cast<size_t>(a)));
  for (size_t c = 0; c < scene.clusters.size(); ++c) {
    const ClusterPair kind = scene.clusters.pair(ca, c);
    for (int b : scene.clusters.members(c)) {
      if (!visitedFrom(scene, a, b)) continue;
      if (kind == ClusterPair::Culled) {
        ++culled;
      } else if (!visit(b, kind == ClusterPair::Free)) {
        return;
      }
    }
  }
}

// How many pairs forPairs would hand `visit` from `a` that the caller's filter keeps (those
// of culled cluster pairs left out): at most the values `a` keeps. It sizes the chunks of
// pairs written into F's rows and the values reserved at once for a process's part (grown
// by doubling, a 6,144-node room's 15.7 M values were allocated, copied and faulted in about
// twice over). Measured against the values kept: equal on the rooms, 0.1–0.3 % more on the
// 6,402- and 19,202-node satellites, 13 % more on the CAD bus (pairs hidden one by one).
size_t pairsFrom(const ExactScene& scene, const ExactOptions& opt, int a);

}  // namespace radnet::geometry
