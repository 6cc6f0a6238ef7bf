#include "solver/radiative/eigenpairs.hpp"

#include "solver/radiative/policy.hpp"
#include "solver/parallel.hpp"

#include <Spectra/MatOp/DenseSymMatProd.h>
#include <Spectra/SymEigsSolver.h>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace radnet::solver {

const char* toString(EigenMethod m) {
  switch (m) {
    case EigenMethod::Auto: return "auto";
    case EigenMethod::Dense: return "dense";
    case EigenMethod::Lanczos: return "lanczos";
  }
  return "unknown";
}

namespace {

// Reorders pairs by decreasing |λ| (eq. 15 keeps the largest magnitudes, of either sign).
EigenPairs sortedByMagnitude(const Eigen::VectorXd& values, const Eigen::MatrixXd& vectors) {
  std::vector<int> order(static_cast<size_t>(values.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return std::abs(values[a]) > std::abs(values[b]); });
  EigenPairs out;
  out.values.resize(values.size());
  out.vectors.resize(vectors.rows(), values.size());
  for (int i = 0; i < values.size(); ++i) {
    out.values[i] = values[order[static_cast<size_t>(i)]];
    out.vectors.col(i) = vectors.col(order[static_cast<size_t>(i)]);
  }
  return out;
}

template <class Op>
EigenPairs runLanczos(Op& op, int n, int nev, int max_iterations, double tolerance) {
  // Krylov basis: nev + min(nev, 120) vectors (at least nev + 20). On the 19,202-node
  // satellite, 200 pairs took 9.0 s with 2 nev + 1 = 401 vectors (4 restarts), 7.4 s with 320
  // (6), 8.2 s with 260 (14) and 14.6 s with 220 (58); 128 pairs 3.4 s with 257, 3.2 s with
  // 248. Re-orthogonalising a basis of 2 nev costs more than the restarts a smaller one adds.
  const int ncv = std::min(n, nev + std::clamp(nev, 20, 120));
  Spectra::SymEigsSolver<Op> eigs(op, nev, ncv);
  eigs.init();
  const Eigen::Index nconv =
      eigs.compute(Spectra::SortRule::LargestMagn, max_iterations, tolerance, Spectra::SortRule::LargestMagn);
  EigenPairs out;
  out.method = EigenMethod::Lanczos;
  out.iterations = static_cast<int>(eigs.num_iterations());
  if (eigs.info() == Spectra::CompInfo::Successful) {
    out = [&] {
      EigenPairs p = sortedByMagnitude(eigs.eigenvalues(), eigs.eigenvectors());
      p.method = EigenMethod::Lanczos;
      p.iterations = static_cast<int>(eigs.num_iterations());
      return p;
    }();
  } else {
    out.status = Status::NotConverged;
    out.message = "Lanczos (Spectra) converged " + std::to_string(nconv) + " of " + std::to_string(nev) +
                  " eigenpairs in " + std::to_string(eigs.num_iterations()) + " restarts";
  }
  return out;
}

}  // namespace

int rankForTolerance(const Eigen::Ref<const Eigen::VectorXd>& values, double tolerance, double max_s) {
  // values sorted by decreasing |λ|: keep until every dropped |λ| · s_max ≤ tolerance.
  int k = static_cast<int>(values.size());
  while (k > 0 && std::abs(values[k - 1]) * max_s <= tolerance) --k;
  return std::max(k, 1);
}

EigenPairs truncate(const EigenPairs& pairs, int k) {
  k = std::clamp(k, 0, pairs.rank());
  EigenPairs out = pairs;
  out.values = pairs.values.head(k);
  out.vectors = pairs.vectors.leftCols(k);
  out.dropped_bound = k < pairs.rank() ? std::abs(pairs.values[k]) : pairs.dropped_bound;
  return out;
}

Eigen::MatrixXd reconstruct(const EigenPairs& pairs) {
  return pairs.vectors * pairs.values.asDiagonal() * pairs.vectors.transpose();
}

EigenPairs denseEigenPairs(const Eigen::Ref<const Eigen::MatrixXd>& g) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(g);
  if (es.info() != Eigen::Success) {
    EigenPairs out;
    out.status = Status::NotConverged;
    out.message = "dense symmetric eigensolver (Eigen) did not converge";
    return out;
  }
  EigenPairs out = sortedByMagnitude(es.eigenvalues(), es.eigenvectors());
  out.method = EigenMethod::Dense;
  return out;
}

EigenPairs lanczosEigenPairs(const SymmetricOperator& op, int nev, int max_iterations, double tolerance) {
  SymmetricOperator copy = op;
  return runLanczos(copy, op.n, nev, max_iterations, tolerance);
}

namespace {

// G x less the pairs already found: y = G x − V (Λ ∘ Vᵀ x). Their directions become zeros, so
// Lanczos on it returns the next pairs by |λ| with a Krylov basis sized for those alone: the
// rank's growth 16 → 32 → 103 → 200 on the 19,202-node satellite re-found every earlier pair,
// and re-orthogonalising a basis of nev + 120 vectors is what a run costs.
template <class Op>
struct DeflatedProduct {
  using Scalar = double;
  const Op& op;
  const EigenPairs& found;
  mutable Eigen::VectorXd weights;  // Λ ∘ Vᵀ x
  Eigen::Index rows() const { return op.rows(); }
  Eigen::Index cols() const { return op.cols(); }
  void perform_op(const double* x, double* y) const {
    op.perform_op(x, y);
    if (found.rank() == 0) return;
    const Eigen::Map<const Eigen::VectorXd> xv(x, op.rows());
    Eigen::Map<Eigen::VectorXd> yv(y, op.rows());
    weights.noalias() = found.vectors.transpose() * xv;
    weights.array() *= found.values.array();
    yv.noalias() -= found.vectors * weights;
  }
};

// The same on a sparse G, on the cores (the product is most of a Lanczos run's time):
// G's column-major arrays read as its rows (G = Gᵀ), so no copy of it is made.
struct DeflatedSparseProduct {
  using Scalar = double;
  Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> g;
  const Eigen::MatrixXd& vectors;
  Eigen::MatrixXd minus_values;  // −Λ (k×k)
  const RowShare& share;         // G's rows shared out: the product joined, whole on every process
  Eigen::Index rows() const { return g.rows(); }
  Eigen::Index cols() const { return g.cols(); }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<Eigen::VectorXd>(y, g.rows()) = sparsePlusLowRankTimes(
        g, vectors, minus_values, vectors, Eigen::Map<const Eigen::VectorXd>(x, g.rows()), share);
  }
};

// A new pair whose |λ| is below this share of the largest found lies in the deflated
// operator's null space, which holds the found directions too: its vector may mix with them
// (measured: overlaps of 0.92 once the rank passed G's 24 non-zero eigenvalues).
constexpr double kNullEigenvalueShare = 1e-9;

// The `found` pairs and `nev` more of the next largest |λ|, sorted by |λ|. `reached_null`:
// a new pair came from the null space (see above); the caller then decomposes afresh.
template <class Product>
EigenPairs nextPairs(Product& deflated, int n, int nev, const EigenRequest& req, const EigenPairs& found,
                     bool& reached_null) {
  EigenPairs more = runLanczos(deflated, n, nev, req.lanczos_max_iterations, req.lanczos_tolerance);
  if (more.status != Status::Converged || found.rank() == 0) return more;
  reached_null = more.values.cwiseAbs().minCoeff() <= kNullEigenvalueShare * std::abs(found.values[0]);
  if (reached_null) return more;
  const int k = found.rank();
  Eigen::VectorXd values(k + nev);
  values << found.values, more.values;
  Eigen::MatrixXd vectors(n, k + nev);
  vectors << found.vectors, more.vectors;
  EigenPairs out = sortedByMagnitude(values, vectors);
  out.method = EigenMethod::Lanczos;
  out.iterations = found.iterations + more.iterations;
  return out;
}

EigenPairs lanczosOnNetwork(const Network& net, int nev, const EigenRequest& req, const EigenPairs& found = {}) {
  const int n = net.size();
  bool reached_null = false;
  EigenPairs out;
  if (net.isSparse()) {
    const Eigen::SparseMatrix<double>& g = net.sparseConductance();
    DeflatedSparseProduct deflated{{n, n, g.nonZeros(), g.outerIndexPtr(), g.innerIndexPtr(), g.valuePtr()},
                                   found.vectors,
                                   -Eigen::MatrixXd(found.values.asDiagonal()),
                                   net.share()};
    out = nextPairs(deflated, n, nev - found.rank(), req, found, reached_null);
  } else {
    const Spectra::DenseSymMatProd<double> op(net.heldDenseConductance());
    DeflatedProduct<Spectra::DenseSymMatProd<double>> deflated{op, found, {}};
    out = nextPairs(deflated, n, nev - found.rank(), req, found, reached_null);
  }
  // G has fewer non-zero eigenvalues than asked: all nev pairs from one run, orthonormal.
  return reached_null ? lanczosOnNetwork(net, nev, req) : out;
}

bool finite(const EigenPairs& p) { return p.values.allFinite() && p.vectors.allFinite(); }

// The rank of a set of pairs from the tolerance: the a-posteriori rule when the request has
// one and it accepts, else the a-priori bound, within the cap.
EigenPairs rankFromTolerance(const EigenPairs& found, const EigenRequest& req, double max_s, int cap,
                             double tolerance = -1.0) {
  if (tolerance < 0) tolerance = req.tolerance;
  const int accepted = req.accept ? req.accept(found) : 0;
  if (accepted > 0) {
    EigenPairs out = truncate(found, std::min(accepted, cap));
    out.rank_rule = accepted <= cap ? "a posteriori" : "rank cap";  // the probes wanted more than the cap
    return out;
  }
  const int apriori = rankForTolerance(found.values, tolerance, max_s);
  const int k_found = found.rank();
  const bool bound_met = apriori < k_found || k_found == found.vectors.rows() ||
                         (k_found > 0 && std::abs(found.values[k_found - 1]) * max_s <= tolerance);
  EigenPairs out = truncate(found, std::min(cap, apriori));
  out.rank_rule = apriori > cap || !bound_met ? "rank cap" : "a-priori bound";
  return out;
}

// Rank from the tolerance by Lanczos: grows the number of pairs until the rank is accepted
// a posteriori, or the smallest pair found already meets the a-priori rule (then every pair
// not found does too, since Lanczos returns the largest |λ|), or the cap.
EigenPairs growLanczos(const Network& net, const EigenRequest& req, double max_s, int cap) {
  const int n = net.size();
  int nev = std::min({16, n - 2, cap});
  EigenPairs found;
  for (;;) {
    found = lanczosOnNetwork(net, nev, req, found);
    if (found.status != Status::Converged) return found;
    EigenPairs result;
    const int accepted = req.accept ? req.accept(found) : 0;
    const bool enough = std::abs(found.values[nev - 1]) * max_s <= req.tolerance;
    if (accepted > 0) {
      result = truncate(found, std::min({accepted, nev, cap}));
      result.rank_rule = "a posteriori";
    } else if (enough || nev >= cap) {
      result = rankFromTolerance(found, EigenRequest{}, max_s, cap, req.tolerance);
    } else if (2 * nev >= n - 1) {  // most of the spectrum is wanted: the dense solver is cheaper
      EigenPairs all = denseEigenPairs(net.denseConductance());
      return all.status != Status::Converged ? all : rankFromTolerance(all, req, max_s, cap);
    } else {
      const int wanted = req.next ? std::max(2 * nev, req.next(nev)) : 2 * nev;
      nev = std::min({wanted, n - 2, cap});  // the last run at the cap exactly
      continue;
    }
    if (result.rank() == nev && nev < n) result.dropped_bound = std::abs(result.values[nev - 1]);  // not yet computed
    return result;
  }
}

}  // namespace

EigenPairs decomposeConductance(const Network& net, const EigenRequest& req) {
  const int n = net.size();
  if (req.rank < 0) throw std::invalid_argument("eigen rank must be >= 0 (0 = from the tolerance)");
  if (req.rank == 0 && !(std::isfinite(req.tolerance) && req.tolerance >= 0))
    throw std::invalid_argument("eigen truncation tolerance must be finite and >= 0");
  const double max_s = req.max_s > 0 ? req.max_s : net.area().cwiseInverse().maxCoeff();
  const int cap = req.max_rank > 0 ? std::min(req.max_rank, n) : n;

  EigenMethod method = policy::eigenMethod(req.method, n, req.rank);
  // No exchange at all (a lone flat plate cut into nodes, nodes that see only space): G = 0
  // has no eigenpair worth keeping, and the iterative solvers fail on a zero matrix.
  if (net.spectralBound() == 0.0) {
    EigenPairs none;
    none.method = method;
    none.vectors = Eigen::MatrixXd::Zero(n, 0);
    none.tolerance = req.rank > 0 ? 0.0 : req.tolerance;
    return none;
  }
  // Spectra needs nev < n and a Krylov space larger than nev.
  if (method == EigenMethod::Lanczos && (n < 4 || req.rank >= n - 1)) method = EigenMethod::Dense;

  const auto dense = [&] {
    EigenPairs all = denseEigenPairs(net.denseConductance());
    if (all.status != Status::Converged) return all;
    return req.rank > 0 ? truncate(all, std::min(req.rank, n)) : rankFromTolerance(all, req, max_s, cap);
  };
  EigenPairs result;
  if (method == EigenMethod::Dense) {
    result = dense();
  } else if (req.rank > 0) {
    result = lanczosOnNetwork(net, req.rank, req);
    result.dropped_bound = result.status == Status::Converged ? std::abs(result.values[result.rank() - 1]) : 0.0;
  } else {
    result = growLanczos(net, req, max_s, cap);
  }
  // A clustered spectrum (a ring of equal nodes: pairs ±λ a relative 1e-5 apart) can defeat
  // Lanczos; `auto` then takes the dense solver where it is affordable, and says so.
  if (req.method == EigenMethod::Auto && result.method == EigenMethod::Lanczos &&
      result.status == Status::NotConverged && n <= policy::kDenseEigenFallbackMaxNodes) {
    const std::string why = result.message;
    result = dense();
    if (result.status == Status::Converged)
      result.fallback = why + "; the dense eigensolver gave the pairs instead (solver.eigensolver: auto)";
  }
  result.tolerance = req.rank > 0 ? 0.0 : req.tolerance;
  if (result.status == Status::Converged && !finite(result)) {
    result.status = Status::NonFinite;
    result.message = "eigenpairs of G are not finite";
  }
  return result;
}

}  // namespace radnet::solver
