#include "geometry/exact/view_factors.hpp"

#include "geometry/exact/integrate_rows.hpp"
#include "geometry/exact/pair_solver.hpp"
#include "geometry/exact/row_plan.hpp"

#include <chrono>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

// Predicted cost of a pair, ns (integers, so that sums do not depend on the thread split):
// measured on bench_exact_view_factors' 1,600-node satellite, about 2 µs an unoccluded
// pair by the contour integral and 0.1 ms an occluded one (430 visibility points of a few
// blockers each); a free pair 0.1 µs (order 0+ and its value's store: 1.2–1.9 s of CPU for
// the 15.7 M of the 6,144-node room). Every pair with a value costs 0.1 µs more of wall time
// (its two entries written into F's and σ's rows, the reciprocity/closure correction): the
// 6,144-node room's stage took 2.36–2.52 s against the 0.79 s its pairs' integrals are
// priced at (docs/view-factor-defaults-benchmark.md, 2026-12-07; 0.15 µs before the pairs
// were written straight into the rows). Held once in the upper triangle (upper_exchange:
// one entry a pair, corrected where it lies) 0.05 µs: the room's stage 1.28–1.44 s against
// 0.79 s of integrals (2026-12-08).
constexpr double kStoredPairSeconds = 0.1e-6, kStoredPairOnceSeconds = 0.05e-6;
std::int64_t pairNanoseconds(PairKind kind, size_t blockers) {
  if (kind == PairKind::Free) return 100;
  if (kind == PairKind::Unoccluded) return 2000;
  if (kind == PairKind::Culled || kind == PairKind::Hidden) return 0;
  return 100000 + 25000 * static_cast<std::int64_t>(blockers);
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
  res.predicted_seconds =
      res.predicted_seconds / threads + double(stored) * (res.upper_exchange ? kStoredPairOnceSeconds : kStoredPairSeconds);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace radnet::geometry
