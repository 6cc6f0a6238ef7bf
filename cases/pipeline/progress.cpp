#include "cases/pipeline/progress.hpp"

#include <unistd.h>
#include <algorithm>
#include <cmath>
#include <atomic>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <memory>
#include <string>

namespace radnet::cases {
namespace {

// A terminal gets a bar redrawn in place; a file or pipe gets plain lines, because every
// '\r' redraw would stay in a log as one endless joined line.
bool isTerminal(const std::ostream& out) { return &out == &std::cerr && ::isatty(STDERR_FILENO) == 1; }

}  // namespace

std::function<void(int, int)> progressBar(std::ostream& out, const char* stage, const char* unit) {
  if (isTerminal(out))
    return [&out, stage, unit](int done, int total) {
      if (total <= 0 || (done != total && done % std::max(1, total / 50) != 0)) return;
      const int filled = 30 * done / total;
      out << "\rradnet: " << stage << " [" << std::string(static_cast<size_t>(filled), '#')
          << std::string(static_cast<size_t>(30 - filled), ' ') << "] " << std::setw(3) << (100 * done / total)
          << " % (" << done << "/" << total << " " << unit << ")" << (done == total ? "\n" : "") << std::flush;
    };
  // Plain lines at 0, 25, 50, 75 and 100 %: each quarter once, whatever order the loop reports.
  auto printed = std::make_shared<std::atomic<int>>(-1);
  return [&out, stage, unit, printed](int done, int total) {
    if (total <= 0) return;
    const int quarter = 4 * done / total;
    int last = printed->load();
    while (quarter > last)
      if (printed->compare_exchange_weak(last, quarter)) {
        out << "radnet: " << stage << " " << 25 * quarter << " % (" << done << "/" << total << " " << unit << ")\n"
            << std::flush;
        return;
      }
  };
}

std::function<void(int, int, int)> thermalProgress(std::ostream& out, double interval_s) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  auto last = std::make_shared<Clock::time_point>(start);
  return [&out, interval_s, start, last](int orbit, int done, int outputs) {
    const Clock::time_point now = Clock::now();
    if (std::chrono::duration<double>(now - *last).count() < interval_s) return;
    *last = now;
    out << "radnet: temperatures: orbit " << orbit << ", output " << done << "/" << outputs << ", "
        << std::lround(std::chrono::duration<double>(now - start).count()) << " s\n"
        << std::flush;
  };
}

}  // namespace radnet::cases
