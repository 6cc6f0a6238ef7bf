#pragma once
// Independent tasks on std::threads, the count OMP_NUM_THREADS sets (the count the rest of
// radnet obeys) or all hardware threads. Each task's arithmetic is the same whatever thread
// runs it, so results do not depend on the count. radnet_solver links no OpenMP (its
// results must be bit-identical for any thread count); this is how it goes parallel.
//
// While the tasks run, Eigen's own products are held to one thread: an Eigen template
// instantiated in a file built with OpenMP may be the copy the linker keeps for all of
// radnet, and OpenMP teams inside every task oversubscribe the cores (measured: 64 optical
// samples took 2.4× longer on 2 cores than one after the other).
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <sched.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

namespace radnet::solver {

inline unsigned threadCount() {
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    const long t = std::strtol(env, nullptr, 10);
    if (t > 0) return static_cast<unsigned>(t);
  }
  // The cores this process may run on, as OpenMP counts them: an MPI rank bound to one
  // core (mpirun's default for few ranks) runs one thread, not one per core of the machine.
  cpu_set_t allowed;
  if (sched_getaffinity(0, sizeof allowed, &allowed) == 0 && CPU_COUNT(&allowed) > 0)
    return static_cast<unsigned>(CPU_COUNT(&allowed));
  return std::max(1u, std::thread::hardware_concurrency());
}

/// body(k) for k in [0, count), on up to `threads` threads (0: threadCount()). The first
/// exception a task throws is rethrown here once every thread has stopped.
template <class Body>
void parallelFor(long long count, const Body& body, unsigned threads = 0) {
  if (count <= 0) return;
  if (threads == 0) threads = threadCount();
  threads = std::max(1u, std::min<unsigned>(threads, static_cast<unsigned>(std::min<long long>(count, 1 << 20))));
  std::atomic<long long> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr first;
  std::atomic_flag storing = ATOMIC_FLAG_INIT;
  auto work = [&] {
    for (long long k = next++; k < count && !failed; k = next++) {
      try {
        body(k);
      } catch (...) {
        if (!storing.test_and_set()) first = std::current_exception();
        failed = true;
      }
    }
  };
  struct OneEigenThread {
    int saved = Eigen::nbThreads();
    OneEigenThread() { Eigen::setNbThreads(1); }
    ~OneEigenThread() { Eigen::setNbThreads(saved); }
  };
  std::optional<OneEigenThread> one_eigen_thread;
  if (threads > 1) one_eigen_thread.emplace();
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) {
    try {  // no thread to spare (a process limit): the ones started and this one do the work
      pool.emplace_back(work);
    } catch (const std::system_error&) {
      break;
    }
  }
  work();
  for (auto& t : pool) t.join();
  one_eigen_thread.reset();
  if (first) std::rethrow_exception(first);
}

/// A compressed row-major matrix read in place: a SparseMatrix or a Map of its arrays (a
/// symmetric column-major matrix's arrays are its rows).
using SparseRowsRef = Eigen::Ref<const Eigen::SparseMatrix<double, Eigen::RowMajor>>;

/// y = S x + U (C (Vᵀ x)) (C empty: the identity), on the cores by fixed blocks of 4,096 rows:
/// Vᵀ x summed block by block in order and each y_i by one task, so y is bit-identical for
/// any thread count. S (n×n), U, V (n×k), C (k×k). The thermal solver's factored GR and
/// Jacobian, and Lanczos on G with the pairs already found deflated.
inline Eigen::VectorXd sparsePlusLowRankTimes(const SparseRowsRef& s, const Eigen::MatrixXd& u,
                                              const Eigen::MatrixXd& c, const Eigen::MatrixXd& v,
                                              const Eigen::Ref<const Eigen::VectorXd>& x) {
  // Fixed blocks (not one per thread), so the sums' order is too; below two blocks' worth a
  // product is too small to share.
  constexpr Eigen::Index kRowsPerBlock = 4096;
  const Eigen::Index n = s.rows(), k = u.cols();
  const Eigen::Index blocks = (n + kRowsPerBlock - 1) / kRowsPerBlock;
  auto rows = [&](Eigen::Index b) { return std::min(kRowsPerBlock, n - b * kRowsPerBlock); };
  Eigen::VectorXd small = Eigen::VectorXd::Zero(k);
  if (k > 0) {
    Eigen::MatrixXd partial(k, blocks);
    parallelFor(blocks, [&](long long b) {
      partial.col(b).noalias() = v.middleRows(b * kRowsPerBlock, rows(b)).transpose() * x.segment(b * kRowsPerBlock, rows(b));
    }, blocks > 1 ? 0 : 1);
    for (Eigen::Index b = 0; b < blocks; ++b) small += partial.col(b);
    if (c.size() > 0) small = c * small;
  }
  Eigen::VectorXd y(n);
  parallelFor(blocks, [&](long long b) {
    auto part = y.segment(b * kRowsPerBlock, rows(b));
    part.noalias() = s.middleRows(b * kRowsPerBlock, rows(b)) * x;
    if (k > 0) part.noalias() += u.middleRows(b * kRowsPerBlock, rows(b)) * small;
  }, blocks > 1 ? 0 : 1);
  return y;
}

}  // namespace radnet::solver
