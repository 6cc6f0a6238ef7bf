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

#include <malloc.h>
#include <sched.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <atomic>
#include <cstdlib>
#include <exception>
#include <functional>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

namespace radnet::solver {

/// Hands the pages the allocator holds free back to the system. glibc keeps what was freed
/// inside its heaps (the worker threads' arenas above all, which the main thread's later
/// allocations do not reuse) resident: after the exact pairs of the 6,144-node room 0.3 GB
/// stayed to the end of the run. Called where a large working set has just been freed.
inline void releaseFreedMemory() { malloc_trim(0); }

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

/// S X for a symmetric sparse S held column-major and compressed, on the cores: S's column
/// arrays read as its rows (S = Sᵀ), in fixed blocks of `rows_per_block` rows, each an Eigen
/// product of its own (every y_ij by one task: bit-identical for any thread count). Eigen's
/// product of a sparse and a dense matrix runs on one thread. With X row-major, Eigen adds
/// whole rows of X (vectorised over its columns) instead of one column at a time: 3× faster
/// for the few hundred columns of an articulation's range finder.
template <class Dense>
Eigen::MatrixXd symmetricTimes(const Eigen::SparseMatrix<double>& s, const Dense& x, Eigen::Index rows_per_block) {
  const Eigen::Index n = s.rows();
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> rows(n, n, s.nonZeros(), s.outerIndexPtr(),
                                                                            s.innerIndexPtr(), s.valuePtr());
  Eigen::MatrixXd y(n, x.cols());
  const Eigen::Index blocks = (n + rows_per_block - 1) / rows_per_block;
  parallelFor(blocks, [&](long long b) {
    const Eigen::Index first = b * rows_per_block, count = std::min(rows_per_block, n - first);
    y.middleRows(first, count).noalias() = rows.middleRows(first, count) * x;
  });
  return y;
}

/// The rows of a network's n × n matrices shared out over processes (MPI ranks,
/// docs/mpi.md): row i is held by one process (holder(i)), and no process holds another's rows
/// (a matrix keeps its n × n shape, the rows it does not hold empty). Vectors of length n,
/// and n × k blocks such as the eigenvectors, stay whole on every process: a product with a
/// shared matrix computes the rows held here, leaves +0.0 in the others, and `join` fills
/// them with their holders' bits. Each row is computed in the same order whatever the
/// number of processes, so every process ends with the same numbers. The functions are the
/// caller's (solver/ and geometry/ know no MPI).
struct RowShare {
  int part = 0;   ///< this process, 0 … parts − 1
  int parts = 1;  ///< number of processes (1: every row here, the functions unused)
  /// In place: each element given by one process (+0.0 on the others) ends with the
  /// giver's bits on every process.
  std::function<void(double*, std::size_t)> join;
  /// In place: the element-wise largest over the processes.
  std::function<void(double*, std::size_t)> max;
  /// send[p] to process p (one per process); returns what every process sent to this one,
  /// concatenated in process order.
  std::function<std::vector<double>(const std::vector<std::vector<double>>&)> exchange;

  bool whole() const { return parts <= 1; }
  /// Row i's process: a hash of i modulo parts. Not i mod parts: a model's node numbering
  /// has periods (front and back sides of a panel alternate), and on 2 ranks one would hold
  /// every back side and twice the entries (measured: 9.2 against 4.3 GB at 50,102 nodes).
  int holder(Eigen::Index row) const {
    if (parts <= 1) return 0;
    std::uint64_t z = static_cast<std::uint64_t>(row) + 0x9e3779b97f4a7c15ULL;  // splitmix64's finaliser
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<int>((z ^ (z >> 31)) % static_cast<std::uint64_t>(parts));
  }
  bool holds(Eigen::Index row) const { return parts <= 1 || holder(row) == part; }
  /// Joins a contiguous block (each element computed by its row's holder).
  void joinRows(double* data, std::size_t count) const {
    if (!whole()) join(data, count);
  }
  /// The largest x over the processes.
  double largest(double x) const {
    if (!whole()) max(&x, 1);
    return x;
  }
  /// Whether any process says yes.
  bool any(bool yes) const { return largest(yes ? 1.0 : 0.0) > 0.0; }
  /// The sum over the processes of a count (exact in doubles below 2⁵³), by the largest of
  /// each process's count in its own slot.
  double total(double count) const {
    if (whole()) return count;
    std::vector<double> slots(static_cast<std::size_t>(parts), 0.0);
    slots[static_cast<std::size_t>(part)] = count;
    join(slots.data(), slots.size());
    double sum = 0.0;
    for (double s : slots) sum += s;
    return sum;
  }
};

/// A compressed row-major matrix read in place: a SparseMatrix or a Map of its arrays (a
/// symmetric column-major matrix's arrays are its rows).
using SparseRowsRef = Eigen::Ref<const Eigen::SparseMatrix<double, Eigen::RowMajor>>;

/// y = S x + U (C (Vᵀ x)) (C empty: the identity), on the cores by fixed blocks of 4,096 rows:
/// Vᵀ x summed block by block in order and each y_i by one task, so y is bit-identical for
/// any thread count. S (n×n), U, V (n×k), C (k×k). The thermal solver's factored GR and
/// Jacobian, and Lanczos on G with the pairs already found deflated. S's rows shared out
/// (`share`): S x from the held rows, joined, then the low-rank part: the same bits.
inline Eigen::VectorXd sparsePlusLowRankTimes(const SparseRowsRef& s, const Eigen::MatrixXd& u,
                                              const Eigen::MatrixXd& c, const Eigen::MatrixXd& v,
                                              const Eigen::Ref<const Eigen::VectorXd>& x,
                                              const RowShare& share = {}) {
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
  const bool whole = share.whole();
  parallelFor(blocks, [&](long long b) {
    auto part = y.segment(b * kRowsPerBlock, rows(b));
    part.noalias() = s.middleRows(b * kRowsPerBlock, rows(b)) * x;
    if (k > 0 && whole) part.noalias() += u.middleRows(b * kRowsPerBlock, rows(b)) * small;
  }, blocks > 1 ? 0 : 1);
  if (whole) return y;
  share.joinRows(y.data(), static_cast<std::size_t>(n));
  if (k > 0)
    parallelFor(blocks, [&](long long b) {
      y.segment(b * kRowsPerBlock, rows(b)).noalias() += u.middleRows(b * kRowsPerBlock, rows(b)) * small;
    }, blocks > 1 ? 0 : 1);
  return y;
}

}  // namespace radnet::solver
