#include "bench/band_methods.hpp"

#include "bench/bench_support.hpp"
#include "solver/radiative/eigenpairs.hpp"
#include "solver/radiative/low_rank_solver.hpp"
#include "solver/radiative/policy.hpp"
#include "solver/radiative/reference_solvers.hpp"

#include <Eigen/SparseLU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <vector>

namespace radnet::bench {
namespace {

using namespace radnet::solver;
using Clock = std::chrono::steady_clock;

struct Row {
  std::string method;
  double setup_s, solve_s, one_rhs_s, rel_error, residual;
  std::string note;
};

std::string sci(double v) {
  std::ostringstream s;
  s << std::scientific << std::setprecision(1) << v;
  return s.str();
}

// Scores an answer against the dense-LU one: max relative error over columns, and the largest
// residual with the full G.
struct Scorer {
  const Network& net;
  const Eigen::VectorXd& rho;
  const Eigen::MatrixXd& mo;
  const Eigen::MatrixXd& m_lu;
  std::pair<double, double> operator()(const Eigen::MatrixXd& m) const {
    const Eigen::Index cols = m.cols();
    double err = 0;
    for (Eigen::Index c = 0; c < cols; ++c) err = std::max(err, (m.col(c) - m_lu.col(c)).norm() / m_lu.col(c).norm());
    const Eigen::VectorXd res = relativeResidual(net.applyConductance(m), net.area(), rho, mo.leftCols(cols), m);
    return {err, res.maxCoeff()};
  }
};

// The low-rank core on the first k pairs: kept, refined to the budget, refined to 1e-10.
void lowRankRows(const BandScene& sc, const EigenPairs& pairs, const std::string& label, const Scorer& score,
                 std::vector<Row>& rows) {
  const int n = sc.net.size();
  auto t0 = Clock::now();
  const LowRankBandSolver band(sc.net, pairs, sc.reflectance);
  const double setup = since(t0);
  t0 = Clock::now();
  band.solve(sc.initial_exitance.col(0));
  const double one = since(t0);
  t0 = Clock::now();
  const BandSolution sol = band.solve(sc.initial_exitance);
  const double solve = since(t0);
  auto [e, r] = score(sol.exitance);
  rows.push_back({"low-rank core " + label, setup, solve, one, e, r,
                  "exact for G'_k; solve includes the residual check (one product with G)"});
  if (pairs.rank() >= n) return;
  for (double tol : {sc.budget_tolerance, 1e-10}) {
    t0 = Clock::now();
    band.solve(sc.initial_exitance.col(0), tol, 500, Refinement::ConjugateGradient);
    const double one_refined = since(t0);
    t0 = Clock::now();
    const BandSolution ref = band.solve(sc.initial_exitance, tol, 500, Refinement::ConjugateGradient);
    const double rsolve = since(t0);
    auto [e2, r2] = score(ref.exitance);
    const std::string what = tol == 1e-10 ? "refinement to 1e-10" : "refinement to " + sci(tol) + " (the budget's)";
    rows.push_back({"low-rank " + label + " + " + what, setup, rsolve, one_refined, e2, r2,
                    std::to_string(ref.refine_iterations) + " batched PCG iterations, " + toString(ref.status)});
  }
}

// The classic iterations and the paper's eigenvector iteration, timed on a few columns and
// scaled to P.
void iterativeRows(const BandScene& sc, const Eigen::MatrixXd& g, const EigenPairs& all, const Scorer& score,
                   std::vector<Row>& rows) {
  const int n = sc.net.size(), P = static_cast<int>(sc.initial_exitance.cols());
  const int sample = n > 3000 ? 4 : 20;
  const BandSystem sys{g, sc.net.area(), sc.reflectance};
  auto iterate = [&](const std::string& name, auto&& fn) {
    Eigen::MatrixXd m(n, sample);
    int iters = 0;
    std::string status = "converged";
    const auto t0 = Clock::now();
    for (int c = 0; c < sample; ++c) {
      const SolveResult r = fn(Eigen::VectorXd(sc.initial_exitance.col(c)));
      m.col(c) = r.exitance;
      iters += r.iterations;
      if (r.status != Status::Converged) status = toString(r.status);
    }
    const double per_column = since(t0) / sample;
    auto [err, res] = score(m);
    rows.push_back({name, 0.0, per_column * P, per_column, err, res,
                    std::to_string(iters / sample) + " iterations per column, " + status + " (timed on " +
                        std::to_string(sample) + " columns, scaled to " + std::to_string(P) + ")"});
  };
  IterativeOptions opt;
  opt.tolerance = 1e-10;
  opt.max_iterations = 20000;
  iterate("Jacobi (eq. 20)", [&](const Eigen::VectorXd& b) { return solveJacobi(sys, b, opt); });
  iterate("Gauss–Seidel", [&](const Eigen::VectorXd& b) { return solveGaussSeidel(sys, b, opt); });
  IterativeOptions sw_opt = opt;
  sw_opt.max_iterations = 200000;
  iterate("Southwell (progressive)", [&](const Eigen::VectorXd& b) { return solveSouthwell(sys, b, sw_opt); });
  iterate("CG on A R⁻¹ − G", [&](const Eigen::VectorXd& b) { return solveConjugateGradient(sys, b, opt); });
  const EigenPairs p32 = truncate(all, std::min(32, all.rank()));
  iterate("paper's eigenvector iteration k = 32 (eqs. 35–37)",
          [&](const Eigen::VectorXd& b) { return solveEigenIteration(p32, sc.net.area(), sc.reflectance, b, opt); });
}

// Sparse LU of I − S G (Eigen::SparseLU, COLAMD ordering), for networks stored sparse.
void sparseLuRow(const BandScene& sc, const Scorer& score, std::vector<Row>& rows) {
  const int n = sc.net.size();
  const Eigen::VectorXd s = sc.reflectance.cwiseQuotient(sc.net.area());
  auto t0 = Clock::now();
  Eigen::SparseMatrix<double> lhs = -(s.asDiagonal() * sc.net.sparseConductance());
  for (int i = 0; i < n; ++i) lhs.coeffRef(i, i) += 1.0;
  lhs.makeCompressed();
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu(lhs);
  const double setup = since(t0);
  if (lu.info() != Eigen::Success) return;
  t0 = Clock::now();
  const Eigen::VectorXd one = lu.solve(Eigen::VectorXd(sc.initial_exitance.col(0)));
  const double one_s = since(t0);
  t0 = Clock::now();
  const Eigen::MatrixXd m = lu.solve(sc.initial_exitance);
  const double solve = since(t0);
  auto [e, r] = score(m);
  rows.push_back({"sparse LU (SparseLU, COLAMD)", setup, solve, one_s, e, r,
                  std::to_string(lhs.nonZeros()) + " non-zeros in I − S G; factors " +
                      std::to_string(lu.nnzL() + lu.nnzU())});
}

void writeTable(const BandScene& sc, const std::vector<Row>& rows, double eig_all, const EigenPairs& all,
                double eig_policy, const EigenPairs& policy_pairs, std::ostream& md) {
  const int n = sc.net.size(), P = static_cast<int>(sc.initial_exitance.cols());
  md << "## " << sc.title << ": n = " << n << " nodes\n\n"
     << "Eigendecomposition of G (once per network, shared by both bands and every optical set): "
     << (sc.lanczos_pairs > 0 ? "Lanczos, " + std::to_string(all.rank()) + " pairs " : std::string("dense, all pairs "))
     << std::setprecision(3) << eig_all << " s; the policy's a-posteriori rank (tolerance " << sc.budget_tolerance
     << ") " << policy_pairs.rank() << " pairs in " << eig_policy << " s (" << policy_pairs.rank_rule << ").\n"
     << "Memory: G " << (sc.net.isSparse() ? "sparse, " : "dense, ") << 8.0 * n * n / 1048576
     << " MiB dense; right-hand sides " << 8.0 * n * P / 1048576 << " MiB.\n\n"
     << "| method | setup per reflectance set (s) | solve " << P << " RHS (s) | solve 1 RHS (s) | speed-up vs LU (setup + "
     << P << ") | max rel. error vs LU | max residual | note |\n|---|---|---|---|---|---|---|---|\n";
  const double base = rows.front().setup_s + rows.front().solve_s;
  for (const Row& r : rows)
    md << "| " << r.method << " | " << std::setprecision(3) << r.setup_s << " | " << r.solve_s << " | " << r.one_rhs_s
       << " | " << base / (r.setup_s + r.solve_s) << "× | " << std::scientific << std::setprecision(2) << r.rel_error
       << " | " << r.residual << std::defaultfloat << " | " << r.note << " |\n";
  md << "\n";
}

}  // namespace

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

void compareBandMethods(const BandScene& sc, std::ostream& md, std::ostream& decay) {
  const int n = sc.net.size();
  const Eigen::MatrixXd& mo = sc.initial_exitance;
  const Eigen::MatrixXd g = sc.net.denseConductance();
  const Eigen::VectorXd s = sc.reflectance.cwiseQuotient(sc.net.area());
  std::vector<Row> rows;
  // Baseline: dense LU, factor once, all columns in one solve.
  auto t0 = Clock::now();
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(Eigen::MatrixXd(Eigen::MatrixXd::Identity(n, n) - s.asDiagonal() * g));
  const double lu_setup = since(t0);
  t0 = Clock::now();
  const Eigen::VectorXd m_one = lu.solve(Eigen::VectorXd(mo.col(0)));  // evaluated: Solve<> is lazy
  const double lu_one = since(t0);
  t0 = Clock::now();
  const Eigen::MatrixXd m_lu = lu.solve(mo);
  const double lu_solve = since(t0);
  const Scorer score{sc.net, sc.reflectance, mo, m_lu};
  {
    auto [e, r] = score(m_lu);
    rows.push_back({"dense LU (baseline)", lu_setup, lu_solve, lu_one, e, r,
                    "O(n³) per reflectance set; 1 RHS agrees to " + sci((m_one - m_lu.col(0)).norm() / m_one.norm())});
  }
  if (sc.net.isSparse()) sparseLuRow(sc, score, rows);

  t0 = Clock::now();
  EigenPairs all;
  if (sc.lanczos_pairs > 0) {
    EigenRequest req;
    req.rank = sc.lanczos_pairs;
    req.method = EigenMethod::Lanczos;
    all = decomposeConductance(sc.net, req);
  } else {
    all = denseEigenPairs(g);
  }
  const double eig_all = since(t0);
  for (int i = 0; i < all.rank(); ++i)
    decay << sc.title << "," << n << "," << i + 1 << "," << std::abs(all.values[i]) / std::abs(all.values[0]) << "\n";
  // What radnet itself keeps: the a-posteriori rank at the budget's tolerance, refinement on.
  SolverSettings settings;
  settings.tolerance = sc.budget_tolerance;
  t0 = Clock::now();
  const EigenPairs policy_pairs = policy::decomposeForBands(sc.net, sc.reflectance, settings);
  const double eig_policy = since(t0);
  lowRankRows(sc, policy_pairs, "k = " + std::to_string(policy_pairs.rank()) + " (radnet's a-posteriori rank)", score,
              rows);
  for (int k : {8, 32, 128, n})
    if (k <= all.rank()) lowRankRows(sc, truncate(all, k), "k = " + std::to_string(k), score, rows);
  iterativeRows(sc, g, all, score, rows);
  writeTable(sc, rows, eig_all, all, eig_policy, policy_pairs, md);
  std::cerr << sc.title << " (n = " << n << ") done\n";
}

}  // namespace radnet::bench
