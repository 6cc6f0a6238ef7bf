#pragma once
// Processes of a shared-rows run (solver::RowShare) played by threads of one test: each
// thread is a part, and the joins, maxima and exchanges go through shared slots between two
// barriers, as MPI's collectives would. Lets a test run 1, 2 or 3 parts without mpirun.
#include "solver/parallel.hpp"

#include <condition_variable>
#include <cstring>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace radnet::testing {

class ThreadedParts {
 public:
  explicit ThreadedParts(int parts) : parts_(parts), slots_(static_cast<size_t>(parts)) {}

  /// body(share) on one thread per part; rethrows the first failure.
  template <class Body>
  void run(const Body& body) {
    std::vector<std::thread> threads;
    std::vector<std::exception_ptr> failed(static_cast<size_t>(parts_));
    for (int p = 0; p < parts_; ++p)
      threads.emplace_back([&, p] {
        try {
          body(share(p));
        } catch (...) {
          failed[static_cast<size_t>(p)] = std::current_exception();
        }
      });
    for (auto& t : threads) t.join();
    for (auto& f : failed)
      if (f) std::rethrow_exception(f);
  }

 private:
  solver::RowShare share(int p) {
    solver::RowShare s;
    s.part = p;
    s.parts = parts_;
    s.join = [this, p](double* data, std::size_t count) {
      combine(p, data, count, [](double& into, double x) {
        std::uint64_t a, b;
        std::memcpy(&a, &into, 8);
        std::memcpy(&b, &x, 8);
        a |= b;
        std::memcpy(&into, &a, 8);
      });
    };
    s.max = [this, p](double* data, std::size_t count) {
      combine(p, data, count, [](double& into, double x) { into = x > into ? x : into; });
    };
    s.exchange = [this, p](const std::vector<std::vector<double>>& send) {
      std::vector<double> flat;  // slot: each destination's part after its length
      for (const auto& to : send) {
        flat.push_back(double(to.size()));
        flat.insert(flat.end(), to.begin(), to.end());
      }
      deposit(p, flat);
      std::vector<double> received;
      for (const auto& slot : slots_) {
        size_t at = 0;
        for (int dest = 0; dest < parts_; ++dest) {
          const auto len = static_cast<size_t>(slot[at++]);
          if (dest == p) received.insert(received.end(), slot.begin() + long(at), slot.begin() + long(at + len));
          at += len;
        }
      }
      barrier();
      return received;
    };
    return s;
  }

  template <class Op>
  void combine(int p, double* data, std::size_t count, const Op& op) {
    deposit(p, std::vector<double>(data, data + count));
    for (int q = 0; q < parts_; ++q)
      if (q != p)
        for (std::size_t k = 0; k < count; ++k) op(data[k], slots_[static_cast<size_t>(q)][k]);
    barrier();  // every part has read the slots before any writes them again
  }

  void deposit(int p, std::vector<double> mine) {
    slots_[static_cast<size_t>(p)] = std::move(mine);
    barrier();
  }

  void barrier() {
    std::unique_lock<std::mutex> lock(mutex_);
    const long generation = generation_;
    if (++arrived_ == parts_) {
      arrived_ = 0;
      ++generation_;
      cv_.notify_all();
    } else {
      cv_.wait(lock, [&] { return generation_ != generation; });
    }
  }

  int parts_;
  std::vector<std::vector<double>> slots_;
  std::mutex mutex_;
  std::condition_variable cv_;
  int arrived_ = 0;
  long generation_ = 0;
};

}  // namespace radnet::testing
