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
#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace radnet::geometry {

struct ReciprocityCorrection {
  Eigen::SparseMatrix<double, Eigen::RowMajor> view_factors;  ///< corrected F: A F symmetric, rows closed
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
  Eigen::VectorXd space, space_error;                           ///< F_space,i and its σ, –
  Eigen::VectorXd blocked, blocked_error;  ///< F_blocked,i (rays stopped by inactive sides) and σ, –
};

/// @param area      node areas, m²
/// @param estimate  estimated F, F_space, F_blocked and their standard errors
/// @param rays      rays cast per node (sets a variance floor of one ray's worth, (1/N)², so that
///                  entries with a zero error estimate are not frozen)
ReciprocityCorrection enforceReciprocity(const Eigen::VectorXd& area, const ViewFactorEstimate& estimate,
                                         const Eigen::VectorXd& rays);

}  // namespace radnet::geometry
