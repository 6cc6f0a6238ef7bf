#include "geometry/exact/view_factors.hpp"

#include "geometry/exact/assemble_rows.hpp"
#include "geometry/exact/clusters.hpp"
#include "geometry/exact/occluded_factor.hpp"
#include "geometry/exact/pair_quadrature.hpp"
#include "geometry/exact/pair_values.hpp"
#include "geometry/exact/patches.hpp"
#include "geometry/exact/polygon_factor.hpp"
#include "geometry/exact/row_plan.hpp"
#include "geometry/exact/shaft.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

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

// Predicted cost of a pair, ns (integers, so that sums do not depend on the thread split):
// measured on bench_exact_view_factors' 1,600-node satellite, about 2 µs an unoccluded
// pair by the contour integral and 0.1 ms an occluded one (430 visibility points of a few
// blockers each); a free pair 0.1 µs (order 0+ and its value's store: 1.2–1.9 s of CPU for
// the 15.7 M of the 6,144-node room). Every pair with a value costs 0.15 µs more of wall time
// after the integrals (its credit to F's rows, the reciprocity/closure correction).
constexpr double kStoredPairSeconds = 0.15e-6;
std::int64_t pairNanoseconds(PairKind kind, size_t blockers) {
  if (kind == PairKind::Free) return 100;
  if (kind == PairKind::Unoccluded) return 2000;
  if (kind == PairKind::Culled || kind == PairKind::Hidden) return 0;
  return 100000 + 25000 * static_cast<std::int64_t>(blockers);
}

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
std::vector<int> exactPatches(const ExactScene& scene) {
  std::vector<int> out;
  for (size_t a = 0; a < scene.patches.size(); ++a)
    if (!scene.sampled[a]) out.push_back(static_cast<int>(a));
  return out;
}

bool visitedFrom(const ExactScene& scene, int a, int b) {
  return b != a && (scene.sampled[static_cast<size_t>(b)] || b > a);
}

// Whether the caller's node-pair filter leaves the pair of patches a, b out.
bool filteredOut(const ExactScene& scene, const ExactOptions& opt, int a, int b) {
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
// of culled cluster pairs left out): at most the values `a` keeps, reserved at once. Grown by
// doubling instead, a 6,144-node room's 15.7 M values were allocated, copied and faulted in
// about twice over (a quarter of the integration's time). Measured against the values kept:
// equal on the rooms, 0.1–0.3 % more on the 6,402- and 19,202-node satellites, 13 % more on
// the CAD bus (pairs hidden one by one); the part never written is never touched.
size_t pairsFrom(const ExactScene& scene, const ExactOptions& opt, int a) {
  const auto ca = static_cast<size_t>(scene.clusters.clusterOf(static_cast<size_t>(a)));
  size_t count = 0;
  for (size_t c = 0; c < scene.clusters.size(); ++c) {
    if (scene.clusters.pair(ca, c) == ClusterPair::Culled) continue;
    for (int b : scene.clusters.members(c)) count += visitedFrom(scene, a, b) && !filteredOut(scene, opt, a, b);
  }
  return count;
}

// Method auto's plan: rows whose pairs would cost more to integrate than to cast, or that
// have a pair of more than max_blockers blockers, are marked for sampling.
// Planning a pair costs too: its occluder candidates are each tested against the pair's
// hull (about 50 ns a candidate on bench_exact_view_factors' scenes), and on a cluttered CAD
// assembly a pair's box holds thousands of them (a 37,706-triangle frame planned for more
// than 10 minutes before this bound). Integers, so that sums do not depend on the threads.
std::int64_t planNanoseconds(size_t candidates) { return 50 * static_cast<std::int64_t>(candidates); }

// Which rows auto leaves to rays: a node with a pair of too many blockers, or whose pairs
// would cost more than casting its row. A patch stops planning as soon as its own pairs
// (planned and predicted) cost more than casting its whole row: the row is cast then, and
// each patch's planning stays bounded by that cost. Returns the pairs planned; `predicted`
// gets the predicted cost of the pairs integrated (s, one thread).
std::int64_t planRows(ExactScene& scene, const ExactOptions& opt, std::vector<char>& rows, int threads,
                      double& predicted, std::int64_t& stored, ExactResult& res) {
  const std::vector<int> exact = exactPatches(scene);
  const size_t n = rows.size();
  const double limit_ns = opt.row_sampling_seconds * 1e9;
  std::vector<std::int64_t> cost(n, 0), entries(n, 0);
  std::vector<char> crowded(n, 0);
  std::int64_t planned = 0, culled = 0, valued = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : planned, culled, valued)
#endif
  {
    PairSolver solver(scene, opt);
    std::vector<std::int64_t> my_cost(n, 0), my_entries(n, 0);
    std::vector<char> my_crowded(n, 0);
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 16)
#endif
    for (size_t k = 0; k < exact.size(); ++k) {
      const int a = exact[k];
      const int node_a = scene.patches[static_cast<size_t>(a)].node;
      std::int64_t patch_ns = 0;
      forPairs(scene, a, culled, [&](int b, bool free) {
        if (filteredOut(scene, opt, a, b)) return true;
        const PairKind kind = free ? PairKind::Free : solver.classify(static_cast<size_t>(a), static_cast<size_t>(b));
        ++planned;
        const bool value = kind == PairKind::Free || kind == PairKind::Unoccluded || kind == PairKind::Occluded;
        valued += value;
        const std::int64_t ns = pairNanoseconds(kind, free ? 0 : solver.blockers());
        patch_ns += ns + (free ? 0 : planNanoseconds(solver.candidates()));
        for (int node : {node_a, scene.patches[static_cast<size_t>(b)].node}) {
          if (node < 0) continue;
          my_cost[static_cast<size_t>(node)] += ns;
          my_entries[static_cast<size_t>(node)] += value;
          if (kind == PairKind::Sampled) my_crowded[static_cast<size_t>(node)] = 1;
        }
        if (node_a >= 0 && limit_ns > 0 && double(patch_ns) > limit_ns) {
          my_crowded[static_cast<size_t>(node_a)] = 1;
          return false;
        }
        return true;
      });
    }
#ifdef _OPENMP
#pragma omp critical(radnet_exact_plan)
#endif
    for (size_t i = 0; i < n; ++i) {
      cost[i] += my_cost[i];
      entries[i] += my_entries[i];
      crowded[i] = crowded[i] || my_crowded[i];
    }
  }
  predicted = detail::concludePlan(opt, cost, crowded, entries, rows, res);
  scene.markSampled(rows);
  stored = valued;
  return planned;
}

// One emitting patch's pairs integrated, handed to store(b, value) when they have a value
// and to skip(b) when not (culled, hidden, left to rays, or zero).
template <class Store, class Skip>
void integratePatch(const ExactScene& scene, const ExactOptions& opt, PairSolver& solver, int a, PairCounts& counts,
                    Store&& store, Skip&& skip) {
  forPairs(scene, a, counts.culled, [&](int b, bool free) {
    if (filteredOut(scene, opt, a, b)) {
      ++counts.culled;
      return true;
    }
    PairKind kind = PairKind::Free;
    if (free)
      solver.setFree(static_cast<size_t>(a), static_cast<size_t>(b));
    else
      kind = solver.classify(static_cast<size_t>(a), static_cast<size_t>(b));
    if (kind == PairKind::Culled || kind == PairKind::Hidden || kind == PairKind::Sampled) {
      (kind == PairKind::Hidden ? counts.hidden : counts.culled) += 1;
      skip(b);
      return true;
    }
    (kind == PairKind::Occluded ? counts.occluded : counts.unoccluded) += 1;
    const FactorEstimate g = solver.integrate(kind);
    counts.by_quadrature += solver.by_quadrature;
    counts.evaluations += g.evaluations;
    if (g.value != 0 || g.error != 0)
      store(b, g);
    else
      skip(b);
    return true;
  });
}

// Counts summed over threads, in a fixed order of fields (integers: any order gives the same).
void addCounts(PairCounts& to, const PairCounts& from) {
  to.culled += from.culled;
  to.hidden += from.hidden;
  to.unoccluded += from.unoccluded;
  to.occluded += from.occluded;
  to.by_quadrature += from.by_quadrature;
  to.evaluations += from.evaluations;
}

// Integrates the emitting patches `exact` into values, per patch (a process's part, to be
// gathered with the others').
PairCounts integratePairs(const ExactScene& scene, const ExactOptions& opt, int threads, const std::vector<int>& exact,
                          std::vector<std::vector<PairValue>>& values) {
  PairCounts counts;
  int finished = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads)
#endif
  {
    PairSolver solver(scene, opt);
    PairCounts mine;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 1)
#endif
    for (size_t k = 0; k < exact.size(); ++k) {
      const int a = exact[k];
      std::vector<PairValue>& to = values[static_cast<size_t>(a)];
      to.reserve(pairsFrom(scene, opt, a));
      integratePatch(
          scene, opt, solver, a, mine,
          [&](int b, const FactorEstimate& g) { to.push_back({b, std::max(g.value, 0.0), g.error}); }, [](int) {});
#ifdef _OPENMP
#pragma omp critical(radnet_exact_progress)
#endif
      {
        ++finished;
        if (opt.progress) opt.progress(finished, static_cast<int>(exact.size()));
      }
    }
#ifdef _OPENMP
#pragma omp critical(radnet_exact_counts)
#endif
    addCounts(counts, mine);
  }
  return counts;
}

// Chunks of emitting patches for PairRowWriter: at most kMaxRowChunks runs of about as many
// pairs each, fewer on large models so that the chunks' row cursors (8 B a chunk and a row)
// stay under 16 MB. More chunks than threads share the pairs out evenly (an occluded pair
// costs a thousand free ones); their number does not change F (PairRowWriter). Returns the
// first position in `exact` of each chunk and, last, exact.size().
constexpr size_t kMaxRowChunks = 128;
std::vector<size_t> rowChunks(const ExactScene& scene, const ExactOptions& opt, int threads,
                              const std::vector<int>& exact, size_t nodes) {
  std::vector<size_t> pairs(exact.size(), 0);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
#endif
  for (size_t k = 0; k < exact.size(); ++k) pairs[k] = pairsFrom(scene, opt, exact[k]);
  (void)threads;
  size_t total = 0;
  for (size_t p : pairs) total += p;
  const size_t wanted = std::clamp<size_t>(size_t(16e6 / 8) / std::max<size_t>(nodes, 1), 1, kMaxRowChunks);
  std::vector<size_t> first{0};
  size_t seen = 0;
  for (size_t k = 0; k < exact.size(); ++k) {
    seen += pairs[k];
    if (first.size() < wanted && seen * wanted >= total * first.size() && k + 1 < exact.size())
      first.push_back(k + 1);
  }
  first.push_back(exact.size());
  return first;
}

// Integrates every pair of which at least one row is exact straight into F's and σ's rows
// (PairRowWriter), chunk by chunk on all threads.
PairCounts integrateIntoRows(const ExactScene& scene, const ExactOptions& opt, int threads,
                             const std::vector<int>& exact, const Eigen::VectorXd& area,
                             const std::vector<char>& sampled_rows, ViewFactorEstimate& out) {
  const std::vector<size_t> chunks = rowChunks(scene, opt, threads, exact, sampled_rows.size());
  const size_t chunk_count = chunks.size() - 1;
  const auto node = [&](int patch) { return scene.patches[static_cast<size_t>(patch)].node; };
  PairRowWriter rows(area, sampled_rows, chunk_count);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
  for (size_t c = 0; c < chunk_count; ++c) {
    std::int64_t culled = 0;
    for (size_t k = chunks[c]; k < chunks[c + 1]; ++k) {
      const int a = exact[k];
      forPairs(scene, a, culled, [&](int b, bool) {
        if (!filteredOut(scene, opt, a, b)) rows.count(c, node(a), node(b));
        return true;
      });
    }
  }
  rows.layout(out);
  PairCounts counts;
  int finished = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads)
#endif
  {
    PairSolver solver(scene, opt);
    PairCounts mine;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 1)
#endif
    for (size_t c = 0; c < chunk_count; ++c)
      for (size_t k = chunks[c]; k < chunks[c + 1]; ++k) {
        const int a = exact[k];
        integratePatch(
            scene, opt, solver, a, mine,
            [&](int b, const FactorEstimate& g) { rows.credit(c, node(a), node(b), std::max(g.value, 0.0), g.error); },
            [&](int b) { rows.skip(c, node(a), node(b)); });
#ifdef _OPENMP
#pragma omp critical(radnet_exact_progress)
#endif
        {
          ++finished;
          if (opt.progress) opt.progress(finished, static_cast<int>(exact.size()));
        }
      }
#ifdef _OPENMP
#pragma omp critical(radnet_exact_counts)
#endif
    addCounts(counts, mine);
  }
  rows.finish(threads);
  return counts;
}

// Every pair of which at least one row is exact into `out`: straight into its rows in one
// process; shared out over processes (opt.parts), each integrates its emitting patches into
// values, gathered and then credited.
PairCounts integrateExactRows(const ExactScene& scene, const ExactOptions& opt, int threads,
                              const Eigen::VectorXd& area, const std::vector<char>& sampled_rows,
                              ViewFactorEstimate& out) {
  const std::vector<int> exact = exactPatches(scene);
  if (opt.parts <= 1) return integrateIntoRows(scene, opt, threads, exact, area, sampled_rows, out);
  std::vector<int> mine;
  for (size_t k = static_cast<size_t>(opt.part); k < exact.size(); k += static_cast<size_t>(opt.parts))
    mine.push_back(exact[k]);
  std::vector<std::vector<PairValue>> values(scene.patches.size());
  const PairCounts counts = unpackParts(opt.gather(packPart(values, integratePairs(scene, opt, threads, mine, values), mine)), values);
  std::vector<int> patch_node;
  for (const Patch& p : scene.patches) patch_node.push_back(p.node);
  assemblePairRows(patch_node, values, area, sampled_rows, threads, out);
  return counts;
}

}  // namespace

ExactResult exactViewFactors(const Scene& scene, const ExactOptions& opt) {
  if (!(opt.tolerance > 0)) throw std::invalid_argument("exact view factors need a tolerance > 0");
  if (opt.parts > 1 && (!opt.gather || opt.part < 0 || opt.part >= opt.parts))
    throw std::invalid_argument("exact view factors shared out need a part in [0, parts) and a gather");
  const auto t0 = std::chrono::steady_clock::now();
#ifdef _OPENMP
  const int threads = opt.threads > 0 ? opt.threads : omp_get_max_threads();
#else
  const int threads = 1;
#endif
  ExactScene shared(scene, threads, opt);
  const size_t n = scene.nodes().size();
  ExactResult res;
  res.sampled_rows = shared.presample(n, opt.max_patches);
  if (!opt.rows.empty()) {
    if (opt.rows.size() != n) throw std::invalid_argument("exact view factors: the row mask must have one entry per node");
    for (size_t i = 0; i < n; ++i) res.sampled_rows[i] = res.sampled_rows[i] || !opt.rows[i];
    shared.markSampled(res.sampled_rows);
  }
  std::int64_t stored = 0;  // pairs the plan expects a value of
  if (opt.max_blockers >= 0 || opt.row_sampling_seconds > 0 || opt.max_entries >= 0)
    res.pairs_planned = planRows(shared, opt, res.sampled_rows, threads, res.predicted_seconds, stored, res);
  Eigen::VectorXd area(static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < area.size(); ++i) area[i] = scene.nodes()[static_cast<size_t>(i)].area_m2;
  const PairCounts counts = integrateExactRows(shared, opt, threads, area, res.sampled_rows, res);
  res.patches = static_cast<int>(shared.patches.size());
  res.pairs_culled = counts.culled;
  res.pairs_hidden = counts.hidden;
  res.pairs_unoccluded = counts.unoccluded;
  res.pairs_occluded = counts.occluded;
  res.pairs_by_quadrature = counts.by_quadrature;
  res.evaluations = counts.evaluations;
  res.threads = threads;
  res.predicted_seconds = res.predicted_seconds / threads + double(stored) * kStoredPairSeconds;
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace radnet::geometry
