#include "geometry/exact/view_factors.hpp"

#include "geometry/exact/occluded_factor.hpp"
#include "geometry/exact/patches.hpp"
#include "geometry/exact/polygon_factor.hpp"
#include "geometry/exact/shaft.hpp"

#include <chrono>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

struct PairValue {
  int q;
  double exchange_area, error;  // A_P F_PQ and its error estimate, m²
};

enum class PairKind { Culled, Hidden, Unoccluded, Occluded, Sampled };

std::vector<Vec3> pointsOf(const Patch& p) {
  std::vector<Vec3> out;
  for (const Loop& l : p.pieces) out.insert(out.end(), l.begin(), l.end());
  return out;
}

bool allBehind(const std::vector<Vec3>& points, const Patch& plane, double tol) {
  for (const Vec3& v : points)
    if (plane.region.normal.dot(v) - plane.offset > tol) return false;
  return true;
}

bool anyBehind(const std::vector<Vec3>& points, const Patch& plane, double tol) {
  for (const Vec3& v : points)
    if (plane.region.normal.dot(v) - plane.offset < -tol) return true;
  return false;
}

// The convex pieces of `a` in front of b's plane.
std::vector<Loop> clippedPieces(const Patch& a, const Patch& b) {
  std::vector<Loop> out;
  const Vec3 point = b.offset * b.region.normal;
  for (const Loop& piece : a.pieces) {
    Loop kept = clipToHalfSpace(piece, point, b.region.normal);
    if (!kept.empty()) out.push_back(std::move(kept));
  }
  return out;
}

// What every thread reads: patches, occluders, and each patch's share of its node's area.
struct ExactScene {
  ExactScene(const Scene& scene) : patches(buildPatches(scene)), index(buildOccluders(scene)) {
    tol = 1e-9 * std::max(scene.extent(), 1e-300);
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
  std::vector<std::vector<Vec3>> points;
  std::vector<double> node_area, share;
  std::vector<char> sampled;  // per patch: its node's row is cast as rays from the start
  double tol = 0.0;           // m: nearer a plane than this counts as on it
};

// Predicted cost of a pair, µs (integers, so that sums do not depend on the thread split):
// measured on bench_exact_view_factors' 1,600-node satellite, about 2 µs an unoccluded pair
// and 0.1 ms an occluded one (430 visibility points of a few blockers each).
std::int64_t pairMicroseconds(PairKind kind, size_t blockers) {
  if (kind == PairKind::Unoccluded) return 2;
  if (kind == PairKind::Culled || kind == PairKind::Hidden) return 0;
  return 100 + 25 * static_cast<std::int64_t>(blockers);
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
  size_t blockers() const { return blockers_.size(); }
  size_t candidates() const { return candidates_.size(); }

  FactorEstimate integrate(PairKind kind) {
    const Patch &p = s_.patches[a_], &q = s_.patches[b_];
    // This pair's share of the target on F_ij and F_ji alike (see docs/geometry.md).
    const double area_i = p.node >= 0 ? s_.node_area[static_cast<size_t>(p.node)] : p.area_m2;
    const double area_j = q.node >= 0 ? s_.node_area[static_cast<size_t>(q.node)] : q.area_m2;
    const double tol = opt_.tolerance * s_.share[a_] * s_.share[b_] * std::min(area_i, area_j);
    if (kind == PairKind::Unoccluded) {
      const PlanarRegion pr = clip_p_ ? PlanarRegion{*p_pieces_, p.region.normal} : p.region;
      const PlanarRegion qr = clip_q_ ? PlanarRegion{*q_pieces_, q.region.normal} : q.region;
      return polygonExchangeArea(pr, qr, tol);
    }
    OccludedPair pair{p_pieces_, p.region.normal, q_pieces_, {}, {}};
    for (int id : blockers_) pair.blockers.push_back(&s_.index.occluders()[static_cast<size_t>(id)]);
    return occludedExchangeArea(pair, tol, opt_.max_depth);
  }

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

// Sums the pair values into F, F_blocked and their error estimates.
void assemble(const std::vector<Patch>& patches, const std::vector<std::vector<PairValue>>& values,
              const Eigen::VectorXd& area, ExactResult& res) {
  const Eigen::Index n = area.size();
  std::vector<Eigen::Triplet<double>> f, e;
  res.blocked = res.blocked_error = Eigen::VectorXd::Zero(n);
  auto credit = [&](int i, int j, double g, double err) {
    if (i < 0 || res.sampled_rows[static_cast<size_t>(i)]) return;
    if (j >= 0) {
      f.emplace_back(i, j, g / area[i]);
      e.emplace_back(i, j, err / area[i]);
    } else {
      res.blocked[i] += g / area[i];
      res.blocked_error[i] += err / area[i];
    }
  };
  for (size_t a = 0; a < values.size(); ++a)
    for (const PairValue& v : values[a]) {
      const int i = patches[a].node, j = patches[static_cast<size_t>(v.q)].node;
      credit(i, j, v.exchange_area, v.error);
      credit(j, i, v.exchange_area, v.error);
    }
  res.view_factors.resize(n, n);
  res.view_factors.setFromTriplets(f.begin(), f.end());
  res.standard_error.resize(n, n);
  res.standard_error.setFromTriplets(e.begin(), e.end());
  res.space.resize(n);
  res.space_error.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (res.sampled_rows[static_cast<size_t>(i)]) {
      res.space[i] = res.space_error[i] = 0.0;
      continue;
    }
    const double row = res.view_factors.row(i).sum() + res.blocked[i];
    res.space[i] = std::max(0.0, 1.0 - row);
    res.space_error[i] = res.standard_error.row(i).sum() + res.blocked_error[i];
  }
}

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

// Method auto's plan: rows whose pairs would cost more to integrate than to cast, or that
// have a pair of more than max_blockers blockers, are marked for sampling.
// Planning a pair costs too: its occluder candidates are each tested against the pair's
// hull (about 50 ns a candidate on bench_exact_view_factors' scenes), and on a cluttered CAD
// assembly a pair's box holds thousands of them (a 37,706-triangle frame planned for more
// than 10 minutes before this bound). Integers, so that sums do not depend on the threads.
std::int64_t planMicroseconds(size_t candidates) { return static_cast<std::int64_t>(candidates / 20); }

// Which rows auto leaves to rays: a node with a pair of too many blockers, or whose pairs
// would cost more than casting its row. A patch stops planning as soon as its own pairs
// (planned and predicted) cost more than casting its whole row: the row is cast then, and
// each patch's planning stays bounded by that cost.
std::int64_t planRows(ExactScene& scene, const ExactOptions& opt, std::vector<char>& rows, int threads) {
  const int np = static_cast<int>(scene.patches.size());
  const std::vector<int> exact = exactPatches(scene);
  const size_t n = rows.size();
  const double limit_us = opt.row_sampling_seconds * 1e6;
  std::vector<std::int64_t> cost(n, 0);
  std::vector<char> crowded(n, 0);
  std::int64_t planned = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : planned)
#endif
  {
    PairSolver solver(scene, opt);
    std::vector<std::int64_t> my_cost(n, 0);
    std::vector<char> my_crowded(n, 0);
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 16)
#endif
    for (size_t k = 0; k < exact.size(); ++k) {
      const int a = exact[k];
      const int node_a = scene.patches[static_cast<size_t>(a)].node;
      std::int64_t patch_us = 0;
      for (int b = 0; b < np; ++b) {
        if (!visitedFrom(scene, a, b)) continue;
        const PairKind kind = solver.classify(static_cast<size_t>(a), static_cast<size_t>(b));
        ++planned;
        const std::int64_t us = pairMicroseconds(kind, solver.blockers());
        patch_us += us + planMicroseconds(solver.candidates());
        for (int node : {node_a, scene.patches[static_cast<size_t>(b)].node}) {
          if (node < 0) continue;
          my_cost[static_cast<size_t>(node)] += us;
          if (kind == PairKind::Sampled) my_crowded[static_cast<size_t>(node)] = 1;
        }
        if (node_a >= 0 && limit_us > 0 && double(patch_us) > limit_us) {
          my_crowded[static_cast<size_t>(node_a)] = 1;
          break;
        }
      }
    }
#ifdef _OPENMP
#pragma omp critical(radnet_exact_plan)
#endif
    for (size_t i = 0; i < n; ++i) {
      cost[i] += my_cost[i];
      crowded[i] = crowded[i] || my_crowded[i];
    }
  }
  for (size_t i = 0; i < n; ++i)
    rows[i] = rows[i] || crowded[i] || (opt.row_sampling_seconds > 0 && double(cost[i]) > limit_us);
  scene.markSampled(rows);
  return planned;
}

struct PairCounts {
  std::int64_t culled = 0, hidden = 0, unoccluded = 0, occluded = 0;
  long long evaluations = 0;
};

// This process's part of the pair values and counts, packed: the counts, then per emitting
// patch it integrated [patch, count, (q, exchange area, error)…].
std::vector<double> packPart(const std::vector<std::vector<PairValue>>& values, const PairCounts& c,
                             const std::vector<int>& mine) {
  std::vector<double> out = {double(c.culled), double(c.hidden), double(c.unoccluded), double(c.occluded),
                             double(c.evaluations), double(mine.size())};
  for (int a : mine) {
    const std::vector<PairValue>& v = values[static_cast<size_t>(a)];
    out.push_back(a);
    out.push_back(static_cast<double>(v.size()));
    for (const PairValue& p : v) out.insert(out.end(), {double(p.q), p.exchange_area, p.error});
  }
  return out;
}

// Every process's parts back into `values`, the counts summed.
PairCounts unpackParts(const std::vector<double>& all, std::vector<std::vector<PairValue>>& values) {
  PairCounts total;
  for (size_t at = 0; at < all.size();) {
    total.culled += static_cast<std::int64_t>(all[at]);
    total.hidden += static_cast<std::int64_t>(all[at + 1]);
    total.unoccluded += static_cast<std::int64_t>(all[at + 2]);
    total.occluded += static_cast<std::int64_t>(all[at + 3]);
    total.evaluations += static_cast<long long>(all[at + 4]);
    const auto patches = static_cast<size_t>(all[at + 5]);
    at += 6;
    for (size_t k = 0; k < patches; ++k) {
      std::vector<PairValue>& v = values[static_cast<size_t>(all[at])];
      const auto count = static_cast<size_t>(all[at + 1]);
      at += 2;
      v.clear();
      for (size_t j = 0; j < count; ++j, at += 3) v.push_back({static_cast<int>(all[at]), all[at + 1], all[at + 2]});
    }
  }
  return total;
}

// Integrates every pair of which at least one row is exact (this process's emitting patches).
PairCounts integratePairs(const ExactScene& scene, const ExactOptions& opt, int threads,
                          std::vector<std::vector<PairValue>>& values) {
  const int np = static_cast<int>(scene.patches.size());
  std::vector<int> exact = exactPatches(scene);
  if (opt.parts > 1) {
    std::vector<int> mine;
    for (size_t k = static_cast<size_t>(opt.part); k < exact.size(); k += static_cast<size_t>(opt.parts))
      mine.push_back(exact[k]);
    exact = std::move(mine);
  }
  std::int64_t culled = 0, hidden = 0, unoccluded = 0, occluded = 0;
  long long evaluations = 0;
  int finished = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : culled, hidden, unoccluded, occluded, evaluations)
#endif
  {
    PairSolver solver(scene, opt);
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 1)
#endif
    for (size_t k = 0; k < exact.size(); ++k) {
      const int a = exact[k];
      for (int b = 0; b < np; ++b) {
        if (!visitedFrom(scene, a, b)) continue;
        const PairKind kind = solver.classify(static_cast<size_t>(a), static_cast<size_t>(b));
        if (kind != PairKind::Unoccluded && kind != PairKind::Occluded) {
          (kind == PairKind::Hidden ? hidden : culled) += 1;
          continue;
        }
        (kind == PairKind::Unoccluded ? unoccluded : occluded) += 1;
        const FactorEstimate g = solver.integrate(kind);
        evaluations += g.evaluations;
        if (g.value != 0 || g.error != 0) values[static_cast<size_t>(a)].push_back({b, std::max(g.value, 0.0), g.error});
      }
#ifdef _OPENMP
#pragma omp critical(radnet_exact_progress)
#endif
      {
        ++finished;
        if (opt.progress) opt.progress(finished, static_cast<int>(exact.size()));
      }
    }
  }
  const PairCounts counts{culled, hidden, unoccluded, occluded, evaluations};
  if (opt.parts <= 1) return counts;
  return unpackParts(opt.gather(packPart(values, counts, exact)), values);
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
  ExactScene shared(scene);
  const size_t n = scene.nodes().size();
  ExactResult res;
  res.sampled_rows = shared.presample(n, opt.max_patches);
  if (opt.max_blockers >= 0 || opt.row_sampling_seconds > 0)
    res.pairs_planned = planRows(shared, opt, res.sampled_rows, threads);
  std::vector<std::vector<PairValue>> values(shared.patches.size());
  const PairCounts counts = integratePairs(shared, opt, threads, values);
  Eigen::VectorXd area(static_cast<Eigen::Index>(n));
  for (Eigen::Index i = 0; i < area.size(); ++i) area[i] = scene.nodes()[static_cast<size_t>(i)].area_m2;
  assemble(shared.patches, values, area, res);
  res.patches = static_cast<int>(shared.patches.size());
  res.pairs_culled = counts.culled;
  res.pairs_hidden = counts.hidden;
  res.pairs_unoccluded = counts.unoccluded;
  res.pairs_occluded = counts.occluded;
  res.evaluations = counts.evaluations;
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace radnet::geometry
