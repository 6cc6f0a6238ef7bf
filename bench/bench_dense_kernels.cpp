// The dense kernels radnet's solver spends its time in, timed for the BLAS question of
// issue 12: built twice by bench/CMakeLists.txt, once on Eigen's own single-threaded
// kernels and once with EIGEN_USE_BLAS + EIGEN_USE_LAPACKE on Debian's threaded OpenBLAS;
// bench/bench_blas.py runs both and writes docs/blas-benchmark.md.
//
// Prints one line per kernel and size: "<kernel> <n> <seconds> <checksum>" (the checksum
// shows both builds computed the same thing).
#include <Eigen/Dense>

#include <chrono>
#include <cstdio>
#include <random>

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// A symmetric conductance-like matrix: non-negative, rows summing below the diagonal area.
Eigen::MatrixXd conductance(int n) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::MatrixXd g(n, n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i <= j; ++i) g(i, j) = g(j, i) = u(rng) / n;
  return g;
}

template <class Body>
void timeKernel(const char* name, int n, Body&& body) {
  const auto t0 = Clock::now();
  const double checksum = body();
  std::printf("%s %d %.6g %.12g\n", name, n, since(t0), checksum);
  std::fflush(stdout);
}

}  // namespace

int main() {
  for (int n : {1024, 2048, 4096}) {
    const Eigen::MatrixXd g = conductance(n);
    const Eigen::MatrixXd v = g.leftCols(128);
    // G V (n × n × 128): the low-rank core's products and the residual checks.
    timeKernel("gemm_n_n_128", n, [&] { return (g * v).sum(); });
    // G G (n³): forming dense GR-like products.
    timeKernel("gemm_n_n_n", n, [&] { return (g * g).sum(); });
    // LU of I − S G: a new reflectance set the dense way, and dense exchange factors.
    timeKernel("lu_factor_solve_360", n, [&] {
      const Eigen::MatrixXd a = Eigen::MatrixXd::Identity(n, n) - 0.5 * g;
      const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a);
      return lu.solve(Eigen::MatrixXd::Ones(n, 360)).sum();
    });
    // All eigenpairs of G: the dense eigendecomposition path (n ≤ 2048 here: O(9 n³)).
    if (n <= 2048)
      timeKernel("dense_eigensolver", n, [&] {
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(g);
        return es.eigenvalues().cwiseAbs().sum();
      });
  }
  return 0;
}
