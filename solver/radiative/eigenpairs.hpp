#pragma once
// Eigenpairs of the conductance matrix G = V Λ Vᵀ (Ashdown 2001, eq. 16), computed ONCE
// per network and shared by every band, reflectance set and orbit position.
#include "solver/radiative/network.hpp"
#include "solver/status.hpp"

#include <Eigen/Dense>

#include <functional>
#include <string>

namespace radnet::solver {

enum class EigenMethod {
  Auto,    ///< dense for small n or when most pairs are needed, Lanczos otherwise
  Dense,   ///< Eigen::SelfAdjointEigenSolver (tridiagonal QR; all n pairs)
  Lanczos  ///< Spectra::SymEigsSolver, implicitly restarted Lanczos, largest |λ|
};

const char* toString(EigenMethod m);

struct EigenPairs;

/// Which eigenpairs to keep.
///
/// Rank from a tolerance (Ashdown §12: dropping eigenvalues below c changes G by at most
/// c in the 2-norm): keep the smallest k with max_{j>k} |λ_j| · s_max ≤ tolerance, where
/// s_max = max_i ρ_i/A_i bounds ‖S‖₂. Then ‖S(G − G'_k)‖₂ ≤ tolerance, an a-priori
/// bound on the relative residual of the truncated solution (times ‖M‖/‖M_o‖).
struct EigenRequest {
  int rank = 0;             ///< k > 0: exactly k pairs (capped at n); 0: from `tolerance`
  double tolerance = 1e-3;  ///< used when rank == 0; see above
  double max_s = 0.0;       ///< s_max = max ρ_i/A_i, 1/m²; 0: use max 1/A_i (ρ ≤ 1)
  int max_rank = 0;         ///< upper limit on k from a tolerance (0: n)
  EigenMethod method = EigenMethod::Auto;
  int lanczos_max_iterations = 1000;
  double lanczos_tolerance = 1e-12;  ///< relative accuracy of Ritz values (Spectra's tol)
  /// A-posteriori acceptance of a rank from a tolerance (solver/radiative/rank_probe.hpp): given the
  /// pairs found so far (largest |λ| first), the rank to keep, or 0 while more pairs are
  /// wanted. Asked before the a-priori rule; empty: the a-priori rule alone.
  std::function<int(const EigenPairs&)> accept;
  /// How many pairs to try after `nev` were not accepted (Lanczos; at least 2 nev is used);
  /// empty: 2 nev.
  std::function<int(int nev)> next;
};

/// Truncated spectral decomposition G'_k = V Λ Vᵀ, |λ_1| ≥ |λ_2| ≥ … .
struct EigenPairs {
  Eigen::VectorXd values;   ///< λ (k), m²
  Eigen::MatrixXd vectors;  ///< V (n×k), orthonormal columns, –
  EigenMethod method = EigenMethod::Dense;
  Status status = Status::Converged;
  std::string message;         ///< why, when status is not Converged
  double tolerance = 0.0;      ///< the truncation tolerance requested (0 for an explicit rank)
  double dropped_bound = 0.0;  ///< largest |λ| not kept (or a bound for it), m²
  int iterations = 0;          ///< Lanczos restarts (0 for dense)
  /// Why this rank: "explicit", "a-priori bound", "rank cap", or the a-posteriori rule's
  /// own reason (solver/radiative/rank_probe.hpp).
  std::string rank_rule = "explicit";
  double probe_residual = -1.0;        ///< a-posteriori: the probes' largest band residual at this rank (−1: not measured)
  double probe_exchange_error = -1.0;  ///< a-posteriori: the probes' largest GR error at this rank (−1: not measured)
  /// Non-empty when `auto` chose Lanczos, Lanczos did not converge and the dense solver gave
  /// these pairs instead: what Lanczos said (a warning for the user, not an error).
  std::string fallback;
  int rank() const { return static_cast<int>(values.size()); }
};

/// A symmetric linear operator y = G x given as a function, for on-the-fly products
/// (Spectra's duck-typed operator concept: rows(), cols(), perform_op()).
struct SymmetricOperator {
  using Scalar = double;
  int n = 0;
  std::function<void(const double* x, double* y)> apply;
  Eigen::Index rows() const { return n; }
  Eigen::Index cols() const { return n; }
  void perform_op(const double* x, double* y) const { apply(x, y); }
};

/// Eigenpairs of the network's conductance matrix per the request.
/// Never throws for numerical reasons: a Lanczos failure is a status.
EigenPairs decomposeConductance(const Network& net, const EigenRequest& request);

/// All eigenpairs of a dense symmetric matrix, sorted by decreasing |λ|.
EigenPairs denseEigenPairs(const Eigen::Ref<const Eigen::MatrixXd>& g);

/// `nev` eigenpairs of largest |λ| of any symmetric operator by Lanczos (Spectra).
EigenPairs lanczosEigenPairs(const SymmetricOperator& op, int nev, int max_iterations, double tolerance);

/// Smallest k meeting the tolerance rule of EigenRequest for values sorted by |λ|.
int rankForTolerance(const Eigen::Ref<const Eigen::VectorXd>& values, double tolerance, double max_s);

/// Keeps the first k pairs.
EigenPairs truncate(const EigenPairs& pairs, int k);

/// Reconstructs G'_k = V Λ Vᵀ (dense; for tests and small networks only).
Eigen::MatrixXd reconstruct(const EigenPairs& pairs);

}  // namespace radnet::solver
