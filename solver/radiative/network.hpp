#pragma once
// The radiative transfer (RT) network of Ashdown 2001, §3–4: n surface nodes with areas
// A_i and form factors F_ij, and its symmetric conductance matrix G = A F (eq. 10, 13).
// Space is the black, cold enclosure of eq. 6 and is not a node: its share of each row
// is F_space,i = 1 − Σ_j F_ij − F_blocked,i.
#include "solver/parallel.hpp"
#include "solver/units.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace radnet::solver {

/// Stefan–Boltzmann constant σ, W m⁻² K⁻⁴ (solver/units.hpp).
using units::kStefanBoltzmann;

/// A caller mistake in network data; the message names the offending node(s) and value.
class NetworkError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Tolerances for accepting measured or rounded form factors.
struct NetworkTolerances {
  /// Allowed excess of a row sum Σ_j F_ij (+ F_blocked,i) over 1 (absolute, view-factor
  /// units). 1e-3 admits tables printed to 4 decimals, as from other tools or papers.
  double row_sum = 1e-3;
  /// Allowed reciprocity defect, in view-factor units: the largest change that the
  /// symmetrisation makes to any F_ij, |A_i F_ij − A_j F_ji| / (2 min(A_i, A_j)).
  double reciprocity = 1e-2;
};

/// What the reciprocity correction did (reported, never silent).
struct ReciprocityReport {
  double max_view_factor_change = 0.0;  ///< largest |ΔF_ij| caused by symmetrising, –
  int worst_from = -1;                  ///< node i of the worst pair (-1: already symmetric)
  int worst_to = -1;                    ///< node j of the worst pair
  double max_row_overshoot = 0.0;       ///< largest Σ_j F_ij − 1 after symmetrising (clipped to F_space = 0), –
};

/// An RT network with a symmetric conductance matrix, dense or sparse.
///
/// Reciprocity enforcement (documented in docs/solver.md): Monte Carlo or rounded form
/// factors give A F that is not exactly symmetric. The conductance used everywhere is the
/// symmetric part G = ½(A F + (A F)ᵀ), the closest symmetric matrix in the Frobenius
/// norm. Each F_ij moves by (A_j F_ji − A_i F_ij)/(2 A_i); the largest move is reported
/// and must stay below NetworkTolerances::reciprocity. F_space is then recomputed from
/// the symmetric G; a row pushed a hair above 1 by the correction gets F_space = 0 and
/// the overshoot is reported.
class Network {
 public:
  /// @param names         node names, unique and non-empty
  /// @param area_m2       node areas A_i, m², finite and > 0
  /// @param view_factors  F (n×n), row i = fractions of power leaving i arriving at j, –
  /// @param blocked       F_blocked,i: fraction of rays from i stopped by inactive sides (may be empty = 0), –
  /// @throws NetworkError naming the bad value when the data are invalid
  Network(std::vector<std::string> names, Eigen::VectorXd area_m2, const Eigen::MatrixXd& view_factors,
          Eigen::VectorXd blocked = {}, NetworkTolerances tolerances = {});
  /// The same, G formed in F's own storage (no n × n copy).
  Network(std::vector<std::string> names, Eigen::VectorXd area_m2, Eigen::MatrixXd&& view_factors,
          Eigen::VectorXd blocked = {}, NetworkTolerances tolerances = {});

  /// Sparse form: the same contract, for networks where most pairs cannot see each other.
  Network(std::vector<std::string> names, Eigen::VectorXd area_m2, const Eigen::SparseMatrix<double>& view_factors,
          Eigen::VectorXd blocked = {}, NetworkTolerances tolerances = {});

  /// Sparse form with F's rows shared out over processes (RowShare, docs/mpi.md): this one
  /// holds rows of F and of Fᵀ (F_ji in row i; the correction's `transposed`), the others
  /// empty, and builds G's held rows, ½(A_i F_ij + A_j F_ji): the one-process G's rows bit
  /// for bit. F_space, the report and every product come out whole on every process.
  Network(std::vector<std::string> names, Eigen::VectorXd area_m2,
          const Eigen::SparseMatrix<double, Eigen::RowMajor>& held_view_factors,
          const Eigen::SparseMatrix<double, Eigen::RowMajor>& held_transposed, Eigen::VectorXd blocked,
          NetworkTolerances tolerances, RowShare share);

  int size() const { return static_cast<int>(names_.size()); }
  /// How G's rows are shared out (whole: every row here).
  const RowShare& share() const { return share_; }
  /// Non-zeros of G over every process.
  long long conductanceNonZeros() const;
  const std::vector<std::string>& names() const { return names_; }
  const Eigen::VectorXd& area() const { return area_; }
  bool isSparse() const { return sparse_; }

  /// Symmetric conductance G = ½(AF + (AF)ᵀ), m². Dense copy (built on demand for sparse networks).
  Eigen::MatrixXd denseConductance() const;
  /// The dense network's own G, m², without a copy (n × n: 288 MiB at 6,144 nodes).
  /// @throws std::logic_error for a sparse network
  const Eigen::MatrixXd& heldDenseConductance() const;
  /// Symmetric conductance in sparse storage (valid only when isSparse()); compressed, so its
  /// column-major arrays, read as rows, are its CSR (G = Gᵀ). Shared rows: the held rows
  /// (columns) only.
  const Eigen::SparseMatrix<double>& sparseConductance() const { return g_sparse_; }
  /// One conductance G_ij, m² (no copy of the matrix).
  /// Shared rows: a collective (every process must ask for the same entry).
  double conductance(int i, int j) const;
  /// Y = G X for a block of vectors, without forming a dense copy of a sparse G (whole on
  /// every process when the rows are shared).
  Eigen::MatrixXd applyConductance(const Eigen::Ref<const Eigen::MatrixXd>& x) const;

  /// Reciprocal form factors F = A⁻¹ G, –.
  Eigen::MatrixXd viewFactors() const;
  /// F_space,i = 1 − Σ_j F_ij − F_blocked,i (after the reciprocity correction), –.
  const Eigen::VectorXd& spaceViewFactor() const { return f_space_; }
  const Eigen::VectorXd& blockedFraction() const { return blocked_; }
  const ReciprocityReport& reciprocity() const { return reciprocity_; }

  /// Gershgorin bound on |λ| of G (Ashdown 2001 §12, eq. 38): max_i Σ_j |G_ij|, m².
  double spectralBound() const;

  /// Index of a node by name, or -1.
  int indexOf(const std::string& name) const;

 private:
  void validateCommon(const NetworkTolerances& tol);
  void finish(const Eigen::VectorXd& row_sums_after, const NetworkTolerances& tol);
  Eigen::VectorXd heldRowSums() const;

  std::vector<std::string> names_;
  Eigen::VectorXd area_;
  Eigen::VectorXd blocked_;
  Eigen::VectorXd f_space_;
  bool sparse_ = false;
  Eigen::MatrixXd g_dense_;
  Eigen::SparseMatrix<double> g_sparse_;
  ReciprocityReport reciprocity_;
  RowShare share_;
};

/// Calls pair(i, j) once for every i > j of an n × n matrix, by 64 × 64 tiles: the
/// transposed side of a large matrix is cache-hostile element by element (symmetrising G
/// and GR in place, copying a triangle to the other). The order is column-major within
/// each tile, tiles down each block column.
template <class Pair>
void forEachLowerPairByTiles(Eigen::Index n, Pair&& pair) {
  constexpr Eigen::Index kTile = 64;
  for (Eigen::Index j0 = 0; j0 < n; j0 += kTile)
    for (Eigen::Index i0 = j0; i0 < n; i0 += kTile)
      for (Eigen::Index j = j0; j < std::min(n, j0 + kTile); ++j)
        for (Eigen::Index i = std::max(i0, j + 1); i < std::min(n, i0 + kTile); ++i) pair(i, j);
}

/// Checks that every entry of a per-node property lies in [lo, hi] and is finite.
/// @throws NetworkError naming the node, the property and the value.
void checkRange(const Network& net, const Eigen::VectorXd& values, const char* what, double lo, double hi);

}  // namespace radnet::solver
