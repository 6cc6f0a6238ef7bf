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

}  // namespace radnet::solver
