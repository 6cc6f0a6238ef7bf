#pragma once
// Reciprocity and closure for Monte Carlo view factors (documented in docs/geometry.md).
//
// The estimates give two noisy values of each conductance, A_i F_ij and A_j F_ji, and row
// sums that fall short of 1 − F_space,i − F_blocked,i once the two are averaged. The
// correction is a constrained weighted least-squares problem: find symmetric g (and the
// space and blocked conductances) minimising Σ (g − ĝ)² / v, v the variance of each
// estimate, subject to Σ_j g_ij + A_i (F_space,i + F_blocked,i) = A_i for every node.
// The solution moves each entry in proportion to its variance (g_ij = ĝ_ij + v_ij (μ_i + μ_j),
// Lagrange multipliers μ from a sparse SPD system), so precise entries barely move and
// zero entries stay zero. Entries driven negative are pinned to zero and the system is
// solved again.
#include "solver/parallel.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <functional>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace radnet::geometry {

struct ReciprocityCorrection {
  ReciprocityCorrection() = default;
  ReciprocityCorrection(const ReciprocityCorrection&) = default;
  ReciprocityCorrection& operator=(const ReciprocityCorrection&) = default;
  /// Moves swap the matrices: Eigen 3.4's sparse matrices have no move of their own, and a
  /// copy of the 6,144-node room's corrected F is 0.38 GB at the stage's peak.
  ReciprocityCorrection(ReciprocityCorrection&& other) noexcept { *this = std::move(other); }
  ReciprocityCorrection& operator=(ReciprocityCorrection&& other) noexcept {
    view_factors.swap(other.view_factors);
    exchange_upper.swap(other.exchange_upper);
    transposed.swap(other.transposed);
    space.swap(other.space);
    blocked.swap(other.blocked);
    max_change = other.max_change, max_change_sigma = other.max_change_sigma;
    worst_from = other.worst_from, worst_to = other.worst_to;
    max_closure_error = other.max_closure_error;
    return *this;
  }

  Eigen::SparseMatrix<double, Eigen::RowMajor> view_factors;  ///< corrected F: A F symmetric, rows closed
  /// Or, corrected from an upper_exchange estimate: the corrected exchange areas g_ij of
  /// j ≥ i (m², view_factors empty); viewFactorsFromUpper() makes F of them.
  Eigen::SparseMatrix<double, Eigen::RowMajor> exchange_upper;
  /// Rows shared out (RowShare): the held rows of Fᵀ (row i: F_ji), which G's held rows need
  /// besides F's; empty otherwise.
  Eigen::SparseMatrix<double, Eigen::RowMajor> transposed;
  Eigen::VectorXd space;                                      ///< corrected F_space
  Eigen::VectorXd blocked;                                    ///< corrected F_blocked
  double max_change = 0.0;                                    ///< largest |ΔF_ij|, view-factor units
  double max_change_sigma = 0.0;                              ///< largest |ΔF_ij| / σ_ij (how many standard errors)
  int worst_from = -1, worst_to = -1;
  double max_closure_error = 0.0;  ///< max_i |Σ_j F_ij + F_space,i + F_blocked,i − 1| after correction
};

/// A view-factor estimate with its standard errors: what the correction weighs. Monte
/// Carlo ray casting (view_factors.hpp) and the contour method both produce one.
struct ViewFactorEstimate {
  Eigen::SparseMatrix<double, Eigen::RowMajor> view_factors;    ///< F (n×n), row = from, –
  Eigen::SparseMatrix<double, Eigen::RowMajor> standard_error;  ///< σ of each F_ij, –
  /// Or, when errors_on_pattern, σ of each F_ij at F_ij's index in view_factors, and
  /// standard_error empty: the exact method's when its caller asks (ExactOptions), σ without
  /// an index array of its own and in single precision (an error estimate needs no more than
  /// float's seven digits, which the exact method keeps everywhere): 0.25 GB less on a
  /// 6,144-node room. errorsOnPattern() views it as a matrix; expandErrors() makes
  /// standard_error of it.
  Eigen::VectorXf error_on_pattern;
  bool errors_on_pattern = false;
  /// Or, when upper_exchange: the exact method's exchange areas g_ij = A_i F_ij = A_j F_ji of
  /// j ≥ i in row i (m²; a node's own g_ii holds both orders of its patch pairs), their
  /// errors (m², float) at the same index, and the node areas A_i they divide by; F and σ
  /// empty (0 × 0). Each pair is integrated once and held once: half of F's and σ's entries
  /// and no index walk between partners (on a 6,144-node room 0.25 GB less memory touched
  /// for the first time). viewFactorsFromUpper() makes F of it, expandUpper() F and σ.
  Eigen::SparseMatrix<double, Eigen::RowMajor> exchange_upper;
  Eigen::VectorXf exchange_error_upper;
  Eigen::VectorXd upper_area;
  bool upper_exchange = false;
  Eigen::VectorXd space, space_error;                           ///< F_space,i and its σ, –
  Eigen::VectorXd blocked, blocked_error;  ///< F_blocked,i (rays stopped by inactive sides) and σ, –
};

/// F's rows from exchange areas held as their upper triangle (g_ij, j ≥ i, m²): F_ij =
/// g_ij / A_i and F_ji = g_ij / A_j, columns in order.
Eigen::SparseMatrix<double, Eigen::RowMajor> viewFactorsFromUpper(
    const Eigen::SparseMatrix<double, Eigen::RowMajor>& upper, const Eigen::VectorXd& area);

/// σ_F over the values of `full` (F as viewFactorsFromUpper laid it out from `upper`, its
/// pattern kept): σ_ij = e_ij / A_i to float's digits, from the errors at upper's indices (m²).
void errorsOverUpperLayout(Eigen::SparseMatrix<double, Eigen::RowMajor>& full,
                           const Eigen::SparseMatrix<double, Eigen::RowMajor>& upper, const Eigen::VectorXd& area,
                           const float* error);

/// The same F laid out dense (n × n), on all cores.
Eigen::MatrixXd denseViewFactorsFromUpper(const Eigen::SparseMatrix<double, Eigen::RowMajor>& upper,
                                          const Eigen::VectorXd& area);

/// The upper triangle's rows cut into `blocks` runs of about equal entries: the first row of
/// each, then n. Fixed by the pattern alone, so sums formed block by block and added in block
/// order are the same bits for any thread count.
std::vector<int> upperRowBlocks(const Eigen::SparseMatrix<double, Eigen::RowMajor>& upper, int blocks);

/// F's entries when its exchange areas are held as their upper triangle.
long long fullNonZeros(const Eigen::SparseMatrix<double, Eigen::RowMajor>& upper);

/// Each row's Σ_j F_ij from the upper exchange areas (summed in a fixed order: the same bits
/// for any thread count).
Eigen::VectorXd upperRowSums(const Eigen::SparseMatrix<double, Eigen::RowMajor>& upper, const Eigen::VectorXd& area);

/// An upper_exchange estimate made an ordinary one (F, and σ on F's pattern); nothing if it
/// is one already.
void expandUpper(ViewFactorEstimate& est);

/// Each row's largest σ_F of an upper_exchange estimate.
Eigen::VectorXd upperRowLargestErrors(const ViewFactorEstimate& est);

/// σ on F's pattern (errors_on_pattern) as a matrix of floats, valid while F's pattern is.
inline Eigen::Map<const Eigen::SparseMatrix<float, Eigen::RowMajor>> errorsOnPattern(const ViewFactorEstimate& est) {
  const auto& f = est.view_factors;
  const float* values = est.error_on_pattern.data();
  return {f.rows(), f.cols(), f.nonZeros(), f.outerIndexPtr(), f.innerIndexPtr(), values, f.innerNonZeroPtr()};
}

/// standard_error made of error_on_pattern (then released); nothing if σ is there already.
inline void expandErrors(ViewFactorEstimate& est) {
  if (!est.errors_on_pattern) return;
  est.standard_error = errorsOnPattern(est).cast<double>();
  Eigen::VectorXf().swap(est.error_on_pattern);
  est.errors_on_pattern = false;
}

/// Each row's largest σ_F, wherever σ is stored.
inline Eigen::VectorXd rowLargestErrors(const ViewFactorEstimate& est) {
  if (est.upper_exchange) return upperRowLargestErrors(est);
  const Eigen::Index n = est.view_factors.rows();
  Eigen::VectorXd largest = Eigen::VectorXd::Zero(n);
  auto scan = [&](const auto& sigma) {
    for (Eigen::Index i = 0; i < sigma.outerSize() && i < n; ++i)
      for (typename std::decay_t<decltype(sigma)>::InnerIterator it(sigma, i); it; ++it)
        largest[i] = std::max(largest[i], double(it.value()));
  };
  if (est.errors_on_pattern)
    scan(errorsOnPattern(est));
  else
    scan(est.standard_error);
  return largest;
}

/// @param area      node areas, m²
/// @param estimate  estimated F, F_space, F_blocked and their standard errors
/// @param rays      rays cast per node (sets a variance floor of one ray's worth, (1/N)², so that
///                  entries with a zero error estimate are not frozen)
ReciprocityCorrection enforceReciprocity(const Eigen::VectorXd& area, const ViewFactorEstimate& estimate,
                                         const Eigen::VectorXd& rays);

/// The same correction, with the corrected F laid over the estimate's own storage: F and σ on
/// one compressed pattern in which every F_ij has its F_ji (the exact method's) are read in
/// place, each pair's ĝ combined again where it is needed, and no pair list, matrix K or
/// second F is made (on a 6,144-node room the correction's peak falls from F, σ, the pairs
/// and the corrected F, 1.5 GB, to F, σ and the pairs' variances, 0.9 GB). The multipliers
/// agree with enforceReciprocity's to their solver tolerance.
/// @param before_overwrite called, when given, once the corrected F's entry count is known
///        and the estimate is still whole (to write it out before it is overwritten)
/// @returns the correction with est.view_factors moved into it (est.standard_error kept; σ on
///          F's pattern, est.error_on_pattern, released with that pattern: read it in
///          before_overwrite), or nothing, est untouched, when F's pattern is not symmetric or
///          σ lies elsewhere. An upper_exchange estimate is corrected pair by pair where each
///          lies: the result holds the corrected exchange areas (exchange_upper), not F.
std::optional<ReciprocityCorrection> enforceReciprocityInPlace(
    const Eigen::VectorXd& area, ViewFactorEstimate& est, const Eigen::VectorXd& rays,
    const std::function<void(long long corrected_nonzeros)>& before_overwrite = {});

/// The same correction with F's rows shared out over processes (solver::RowShare): each
/// holds its rows of `estimate` (the vectors whole), receives the partner entries F_ji of
/// its rows from their holders, and solves for the multipliers by Jacobi-preconditioned
/// conjugate gradients on its rows of K with every vector whole, so every process moves
/// the entries it holds exactly as its partners do. Returns the held rows of the corrected
/// F and of Fᵀ, and the whole space and blocked terms and report. The same for any number
/// of processes bit for bit; against enforceReciprocity, equal to the multipliers' solver
/// tolerance (1e-13 of the residual).
ReciprocityCorrection enforceReciprocityOnRows(const Eigen::VectorXd& area, const ViewFactorEstimate& estimate,
                                               const Eigen::VectorXd& rays, const solver::RowShare& share);

/// `estimate` itself when σ lies on F's compressed pattern entry for entry (as both methods
/// make them), else a copy so laid in `storage` (σ 0 where it held nothing): what the
/// corrections read.
const ViewFactorEstimate& onOnePattern(const ViewFactorEstimate& estimate, ViewFactorEstimate& storage);

/// How far each held entry moved (in F's units and in standard errors) and the rows'
/// closure, into `out`'s report: the largest over the processes (the first pair in row
/// order among equal moves).
void reportCorrection(const ViewFactorEstimate& estimate, const Eigen::VectorXd& rays, ReciprocityCorrection& out,
                      const solver::RowShare& share = {});

}  // namespace radnet::geometry
