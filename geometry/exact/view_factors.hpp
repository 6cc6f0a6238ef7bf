#pragma once
// Deterministic view factors (docs/geometry.md, "Deterministic view factors"): every pair
// of patches is culled (behind either plane), clipped where one straddles the other's
// plane, and shaft-tested against the occluders. Unoccluded pairs get the exact
// polygon-to-polygon factor (double contour integral, polygon_factor.hpp); pairs with
// blockers the adaptive emitter quadrature of exact point visibility (occluded_factor.hpp).
// Each pair is computed once and credited both ways, so A F is symmetric by
// construction; each carries an error estimate. Pairs are visited cluster pair by cluster
// pair (clusters.hpp): culled and free (whole, unoccluded) cluster pairs settle all their
// patch pairs at once, and free pairs far enough apart take a few-point rule
// (pair_quadrature.hpp) instead of the contour integral.
#include "geometry/reciprocity.hpp"
#include "geometry/scene/scene.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace radnet::geometry {

/// Method auto's default for ExactOptions::max_blockers: beyond this many blockers an
/// occluded pair's quadrature costs more than casting its rows (bench_view_factors).
constexpr int kAutoMaxBlockers = 8;
/// Method auto's default for ExactOptions::max_patches: a node of more flat patches than
/// this (a finely facetted curved surface) has its row cast as rays from the start.
constexpr int kAutoMaxPatches = 64;
/// One ray of the Monte Carlo method on one core, s: what method auto weighs against. The
/// four-wide caster casts 8 M rays/s per core on the bench satellites (16.1–16.8 M/s on two
/// cores, 1,602 nodes; docs/view-factor-defaults-benchmark.md); 6.7 M/s is assumed.
constexpr double kSecondsPerRay = 1.5e-7;
/// Rays a row takes under a target error (rays stop when the row's largest entries reach
/// their σ, at most the cap): 12,884 on average on the 1,602-node satellite's cast rows at
/// target 1e-3 (cap 100,000), the figure auto prices a row at when rays are not pinned.
constexpr double kRaysPerRowUnderTarget = 16384;

struct ExactOptions {
  /// Target absolute error of every F_ij (view-factor units).
  double tolerance = 1e-6;
  /// Target error of every pair relative to its value (0: the absolute target alone). A
  /// pair meets the larger of the two; the error budget sets this (docs/solver.md).
  double relative_tolerance = 0.0;
  int max_depth = 8;  ///< deepest 4-way split of an emitter triangle of an occluded pair
  /// Pairs with more blockers than this are left to sampling (`auto`): their nodes'
  /// rows come out empty and are listed in sampled_rows. −1: no limit (`exact`).
  int max_blockers = -1;
  /// Nodes of more patches than this are left to sampling from the start, and pairs
  /// between two such rows are not integrated at all. −1: no limit.
  int max_patches = -1;
  /// What casting one row costs, s (auto): rows whose pairs are predicted to cost more
  /// are cast instead. 0: never for cost.
  double row_sampling_seconds = 0.0;
  /// At most this many entries of F from integrated pairs (auto, set from the memory the
  /// process may use): beyond it the rows with the most entries are cast instead, whose
  /// rows hold at most one entry per distinct node hit. −1: no limit.
  std::int64_t max_entries = -1;
  int threads = 0;    ///< 0: OpenMP's default
  /// σ left on F's pattern (ViewFactorEstimate::error_on_pattern, standard_error empty): for
  /// a caller that corrects in place and reads σ only while F's pattern stands.
  bool errors_on_pattern = false;
  /// Each pair's exchange area held once, in the upper triangle (ViewFactorEstimate::
  /// upper_exchange), when every row is integrated on one process with no row mask or pair
  /// filter (else as errors_on_pattern says): for a caller that corrects with
  /// enforceReciprocityInPlace and reads F through it.
  bool upper_exchange = false;
  /// Called as emitting patches finish (one thread at a time): (done, total).
  std::function<void(int, int)> progress;
  /// Per node (empty: all): only these rows are integrated; the others are left out as rows
  /// sampled elsewhere (their pairs with the rows asked are integrated and credited to the
  /// rows asked alone). A turning part's configuration recomputes its changing rows so.
  std::vector<char> rows;
  /// Which pairs of nodes (i, j ≥ 0) to integrate (null: all): the others are skipped, their
  /// entries left to the caller (a turning part's configuration keeps the base's where no
  /// turn can change them). Pairs with an inactive side are always integrated (F_blocked).
  std::function<bool(int, int)> node_pairs;
  /// The pair integrals shared out over `parts` processes (MPI ranks, docs/mpi.md): this
  /// one integrates the emitting patches k (in plan order) with k % parts == part, and
  /// `gather` returns every process's packed values concatenated in process order. Each
  /// pair's value does not depend on who integrates it: the result is the same bit for bit.
  int part = 0, parts = 1;
  std::function<std::vector<double>(const std::vector<double>&)> gather;

  static ExactOptions withTolerance(double t) {
    ExactOptions o;
    o.tolerance = t;
    return o;
  }
};

struct ExactResult : ViewFactorEstimate {
  int patches = 0;
  std::int64_t pairs_culled = 0;      ///< behind a plane, or neither row integrated
  std::int64_t pairs_hidden = 0;      ///< one occluder hides all of one from all of the other
  std::int64_t pairs_unoccluded = 0;  ///< exact contour integral
  std::int64_t pairs_occluded = 0;    ///< quadrature with exact point visibility
  std::int64_t pairs_planned = 0;     ///< pairs classified while auto chose the rows (a patch stops at its row's cost)
  std::int64_t pairs_by_quadrature = 0;  ///< unoccluded pairs settled by point rules (pair_quadrature.hpp)
  /// What auto's plan predicted the integrated pairs to cost, s of wall time on `threads`
  /// (0 without a plan).
  double predicted_seconds = 0.0;
  int threads = 1;  ///< threads the pairs were integrated on
  /// Per node: 1 when its row is left to ray casting (empty here, space and blocked 0).
  std::vector<char> sampled_rows;
  int rows_for_memory = 0;            ///< of those, left to rays by max_entries
  /// auto's plan, per node: the predicted cost of the pairs its row holds, ns on one thread
  /// (a pair counted on both its rows); empty when nothing was planned.
  std::vector<std::int64_t> row_nanoseconds;
  std::int64_t entries_for_memory = 0;  ///< the entries their pairs would have made
  long long evaluations = 0;          ///< integrand evaluations (outer contour points, visibility points)
  /// The entry of F whose error estimate is largest against its target max(tolerance,
  /// relative_tolerance × F_ij) (the first of equals in row order): above it only where
  /// occluded pairs reached max_depth.
  double worst_error = 0.0, worst_error_target = 0.0;
  double seconds = 0.0;
};

/// All rows; standard_error holds the error estimates. Deterministic for any thread count.
ExactResult exactViewFactors(const Scene& scene, const ExactOptions& options);

/// The estimate with the rows marked in `rows` taken from `sampled` (F, σ, space, blocked).
ViewFactorEstimate withSampledRows(const ViewFactorEstimate& exact, const ViewFactorEstimate& sampled,
                                   const std::vector<char>& rows);

}  // namespace radnet::geometry
