#pragma once
// The rank of the decomposition a posteriori (docs/solver.md, "Rank a posteriori"). The
// a-priori rule |λ_k+1| s_max ≤ τ covers the worst right-hand side on the smallest node;
// on the 1,602-node satellite it asks for more than 400 pairs where 64 already give the
// refinement a residual below 1e-3. Here the rank-k answers are measured instead, with the
// full G, on fixed probe right-hand sides, and the smallest rank that does the job is kept.
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/network.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace radnet::solver {

/// What the rank must achieve on the probes.
struct RankTargets {
  /// Per node, the largest reflectance either band or any optical set gives it, –.
  Eigen::VectorXd reflectance;
  /// Largest relative residual ‖M_o − (I − S G) M‖/‖M_o‖ of a rank-k band solve: the
  /// solver tolerance when the rank-k answer is kept, a looser start for refinement.
  double band_residual = 1e-2;
  /// The band solves are refined to the tolerance after the rank-k answer (a stalled band
  /// residual may then stop the growth); false: the rank-k answers are kept as they are.
  bool band_refined = true;
  /// When GR comes from the pairs (E G E + E V (C − Λ) Vᵀ E): the largest error of GR x on
  /// the probes relative to ε_i A_i max x, with ε = 1 − reflectance; 0: GR is exact (dense LU)
  /// and only the band residual counts.
  double exchange_error = 0.0;
  /// GR may fall back to dense LU when the pairs miss `exchange_error` (policy::exchangeFactors
  /// up to kDenseBandSolveMaxNodes): a stalled GR error then stops the growth as a stalled
  /// band residual does.
  bool exchange_fallback = false;
  /// The emissivities GR is formed with (every optical set's, ε per node); empty: 1 − reflectance.
  std::vector<Eigen::VectorXd> emissivities;
};

/// One measurement of a rank on the probes.
struct RankMeasure {
  int rank = 0;
  double band_residual = 0.0;   ///< largest relative residual of the probes' band solves
  double exchange_error = 0.0;  ///< largest relative error of GR x (0 when not asked)
};

/// The EigenRequest::accept hook: the smallest rank (halving from the pairs found, down to
/// kMinRank) whose measurement meets the targets; "keep all" when what misses its target
/// falls more slowly than 1/k since the last run (the band residual, which refinement
/// finishes, and the GR error when GR can fall back to dense LU); 0 while more pairs are wanted.
class RankProbe {
 public:
  static constexpr int kProbes = 4;   ///< uniform and three random fields (fixed seed)
  static constexpr int kMinRank = 8;  ///< the smallest rank tried
  /// @throws std::invalid_argument when the reflectance does not fit the network
  RankProbe(const Network& net, RankTargets targets, unsigned seed = 1);

  int operator()(const EigenPairs& found);
  /// The number of pairs to try next after `nev` were not enough: where the last two
  /// measurements' power-law decay (error ∝ k^slope) meets the targets, with 20 % margin; at
  /// least 2 nev (the EigenRequest::next hook).
  int nextRank(int nev) const;
  /// The same from `now` (measured at nev pairs) and the run history_[before_at] before it.
  int nextRank(int nev, const RankMeasure& now, size_t before_at) const;
  /// Measures the first k pairs (k ≤ found.rank()).
  RankMeasure measure(const EigenPairs& found, int k);
  /// Why the last accepted rank was accepted ("" before one was).
  const std::string& rule() const { return rule_; }

 private:
  bool meets(const RankMeasure& m) const;
  bool exchangeReferences(const EigenPairs& found);
  double exchangeError(const LowRankBandSolver& band, const Eigen::VectorXd& eps,
                       const Eigen::MatrixXd& reference) const;

  const Network& net_;
  RankTargets targets_;
  Eigen::MatrixXd probes_;         ///< n × kProbes, values in [0, 1]
  std::vector<Eigen::MatrixXd> reference_gr_x_;  ///< GR x per emissivity set with the full G (refined), once
  bool reference_failed_ = false;
  std::vector<RankMeasure> history_;  ///< the measurement of every set of pairs found, in order
  std::string rule_;
};

}  // namespace radnet::solver
