#include "geometry/exact/integrate_rows.hpp"

#include "geometry/exact/assemble_rows.hpp"

#include <algorithm>
#include <numeric>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

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

// Integrates the emitting patches `exact` on all threads, each run [runs[r], runs[r + 1]) of
// them on one thread in order; store(r, a, b, value) and skip(r, a, b) take each pair.
template <class Store, class Skip>
PairCounts integrateRuns(const ExactScene& scene, const ExactOptions& opt, int threads, const std::vector<int>& exact,
                         const std::vector<size_t>& runs, Store&& store, Skip&& skip) {
  PairCounts counts;
  int finished = 0;
  const size_t run_count = runs.size() - 1;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads)
#endif
  {
    PairSolver solver(scene, opt);
    PairCounts mine;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 1)
#endif
    for (size_t r = 0; r < run_count; ++r)
      for (size_t k = runs[r]; k < runs[r + 1]; ++k) {
        const int a = exact[k];
        integratePatch(
            scene, opt, solver, a, mine, [&](int b, const FactorEstimate& g) { store(r, a, b, g); },
            [&](int b) { skip(r, a, b); });
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
  (void)threads;
  return counts;
}

// Integrates the emitting patches `exact` into values, per patch (a process's part, to be
// gathered with the others'), each patch's values reserved at once.
PairCounts integratePairs(const ExactScene& scene, const ExactOptions& opt, int threads, const std::vector<int>& exact,
                          std::vector<std::vector<PairValue>>& values) {
  std::vector<size_t> runs(exact.size() + 1);
  std::iota(runs.begin(), runs.end(), size_t(0));  // a patch a run
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads)
#endif
  for (size_t k = 0; k < exact.size(); ++k)
    values[static_cast<size_t>(exact[k])].reserve(pairsFrom(scene, opt, exact[k]));
  return integrateRuns(
      scene, opt, threads, exact, runs,
      [&](size_t, int a, int b, const FactorEstimate& g) {
        values[static_cast<size_t>(a)].push_back({b, std::max(g.value, 0.0), g.error});
      },
      [](size_t, int, int) {});
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
  return equalRuns(pairs, std::clamp<size_t>(size_t(16e6 / 8) / std::max<size_t>(nodes, 1), 1, kMaxRowChunks));
}

// Integrates every pair of which at least one row is exact straight into F's and σ's rows
// (PairRowWriter), chunk by chunk on all threads.
PairCounts integrateIntoRows(const ExactScene& scene, const ExactOptions& opt, int threads,
                             const std::vector<int>& exact, const Eigen::VectorXd& area,
                             const std::vector<char>& sampled_rows, ExactResult& out) {
  const std::vector<size_t> chunks = rowChunks(scene, opt, threads, exact, sampled_rows.size());
  const size_t chunk_count = chunks.size() - 1;
  const auto node = [&](int patch) { return scene.patches[static_cast<size_t>(patch)].node; };
  const bool upper = opt.upper_exchange && opt.rows.empty() && !opt.node_pairs &&
                     std::find(sampled_rows.begin(), sampled_rows.end(), 1) == sampled_rows.end();
  PairRowWriter rows(area, sampled_rows, chunk_count, opt.errors_on_pattern, upper);
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
  const PairCounts counts = integrateRuns(
      scene, opt, threads, exact, chunks,
      [&](size_t c, int a, int b, const FactorEstimate& g) {
        rows.credit(c, node(a), node(b), std::max(g.value, 0.0), g.error);
      },
      [&](size_t c, int a, int b) { rows.skip(c, node(a), node(b)); });
  const ErrorAgainstTarget worst = rows.finish(threads, {opt.tolerance, opt.relative_tolerance});
  out.worst_error = worst.error;
  out.worst_error_target = worst.target;
  return counts;
}

}  // namespace

PairCounts integrateExactRows(const ExactScene& scene, const ExactOptions& opt, int threads,
                              const Eigen::VectorXd& area, const std::vector<char>& sampled_rows, ExactResult& out) {
  const std::vector<int> exact = exactPatches(scene);
  if (opt.parts <= 1) return integrateIntoRows(scene, opt, threads, exact, area, sampled_rows, out);
  std::vector<int> mine;
  for (size_t k = static_cast<size_t>(opt.part); k < exact.size(); k += static_cast<size_t>(opt.parts))
    mine.push_back(exact[k]);
  std::vector<std::vector<PairValue>> values(scene.patches.size());
  const PairCounts counts =
      unpackParts(opt.gather(packPart(values, integratePairs(scene, opt, threads, mine, values), mine)), values);
  std::vector<int> patch_node;
  for (const Patch& p : scene.patches) patch_node.push_back(p.node);
  const ErrorAgainstTarget worst =
      assemblePairRows(patch_node, values, area, sampled_rows, {opt.tolerance, opt.relative_tolerance}, threads, out,
                       opt.errors_on_pattern);
  out.worst_error = worst.error;
  out.worst_error_target = worst.target;
  return counts;
}

}  // namespace radnet::geometry
