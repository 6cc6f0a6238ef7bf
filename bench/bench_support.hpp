#pragma once
// What every benchmark measures with: wall-clock seconds and peak resident memory.
#include <sys/resource.h>

#include <chrono>

namespace radnet::bench {

/// Peak resident memory of this process so far, MiB (Linux reports ru_maxrss in KiB).
inline double peakMiB() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

/// Seconds since t0.
inline double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace radnet::bench
