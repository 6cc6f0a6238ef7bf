#include "cases/pipeline/progress.hpp"

#include <algorithm>
#include <iomanip>
#include <ostream>

namespace radnet::cases {

std::function<void(int, int)> progressBar(std::ostream& out, const char* stage, const char* unit) {
  return [&out, stage, unit](int done, int total) {
    if (done == total || done % std::max(1, total / 50) == 0)
      out << "\rradnet: " << stage << " " << std::setw(3) << (100 * done / total) << " % (" << done << "/" << total
          << " " << unit << ")" << (done == total ? "\n" : "") << std::flush;
  };
}

}  // namespace radnet::cases
