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
  Eigen::VectorXd space;    ///< corrected F_space
  Eigen::VectorXd blocked;  ///< corrected F_blocked
  double max_change = 0.0;        ///< largest |ΔF_ij|, view-factor units
  double max_change_sigma = 0.0;  ///< largest |ΔF_ij| / σ_ij (how many standard errors)
  int worst_from = -1, worst_to = -1;
  double max_closure_error = 0.0;  ///< max_i |Σ_j F_ij + F_space,i + F_blocked,i − 1| after correction
};

/// @param area  node areas, m²
/// @param f, sigma  estimated F and its standard errors (n×n, row = from)
/// @param space, space_sigma, blocked, blocked_sigma  per-node estimates and standard errors
/// @param rays  rays cast per node (sets a variance floor of one ray's worth, (1/N)², so that
///              entries with a zero error estimate are not frozen)
ReciprocityCorrection enforceReciprocity(const Eigen::VectorXd& area,
                                         const Eigen::SparseMatrix<double, Eigen::RowMajor>& f,
                                         const Eigen::SparseMatrix<double, Eigen::RowMajor>& sigma,
                                         const Eigen::VectorXd& space, const Eigen::VectorXd& space_sigma,
                                         const Eigen::VectorXd& blocked, const Eigen::VectorXd& blocked_sigma,
                                         const Eigen::VectorXd& rays);

}  // namespace radnet::geometry
