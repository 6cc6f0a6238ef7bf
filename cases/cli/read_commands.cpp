#include "cases/cli/read_commands.hpp"

#include "cases/config/case_file.hpp"
#include "cases/config/work_estimate.hpp"
#include "cases/config/damaged_file_guard.hpp"
#include "cases/output/hdf5_reader.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <vector>

namespace radnet::cases {
namespace {
constexpr int kExitBadInput = 2;  // as main.cpp's
constexpr int kExitOutput = 4;
}  // namespace

// The report's tables and figures are drawn by docs/radnet_report.py with Debian's python3,
// h5py and matplotlib: found beside the executable's source tree or installed beside it.
int reportCommand(const std::string& result, std::string dir, const std::string& limits) {
  namespace fs = std::filesystem;
  std::vector<fs::path> candidates = {fs::path(RADNET_SOURCE_DIR) / "docs" / "radnet_report.py"};
  std::error_code ec;
  const fs::path self = fs::canonical(fs::path("/proc/self/exe"), ec);
  if (!ec) candidates.push_back(self.parent_path().parent_path() / "share" / "radnet" / "radnet_report.py");
  const auto script = std::find_if(candidates.begin(), candidates.end(), [](const fs::path& p) { return fs::exists(p); });
  if (script == candidates.end()) {
    std::cerr << "radnet report: docs/radnet_report.py not found (looked in " << candidates.front() << ")\n";
    return kExitOutput;
  }
  if (!fs::exists(result)) {
    std::cerr << result << ":0:0: no such file\n";
    return kExitBadInput;
  }
  // h5py crashes on a damaged file as HDF5 does for us (python3 ends with SIGSEGV): try the
  // whole file in a child first, so such a file is exit 2 naming it, never a crash.
  tryReadInChild(result, [&] { Hdf5Reader(result).readEverything(); });
  if (dir.empty()) dir = (fs::path(result).parent_path() / fs::path(result).stem()).string() + "-report";
  const auto quote = [](const std::string& s) {
    std::string q = "'";
    for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return q + "'";
  };
  std::string command = "/usr/bin/python3 " + quote(script->string()) + " " + quote(result) + " " + quote(dir);
  if (!limits.empty()) command += " --limits " + quote(limits);
  const int status = std::system(command.c_str());
  if (status == -1 || !WIFEXITED(status)) return kExitOutput;
  return WEXITSTATUS(status);
}

// Reads and checks each case, prints its warnings and a size estimate; computes nothing.
int validateCommand(const std::vector<std::string>& paths, const Guard& guarded) {
  int worst = 0;
  for (const std::string& path : paths)
    worst = std::max(worst, guarded([&] {
                       const LoadedCase c = loadCase(path);
                       if (c.geometry) {
                         for (const auto& w : c.geometry->scene.warnings())
                           std::cerr << path << ": warning: " << w << "\n";
                         for (const auto& w : c.geometry->warnings)  // a located one names its file itself
                           std::cerr << (w.rfind(path + ":", 0) == 0 ? "radnet" : path) << ": warning: " << w << "\n";
                       }
                       const ThermalSettings* thermal = c.network && c.network->thermal    ? &*c.network->thermal
                                                        : c.geometry && c.geometry->thermal ? &*c.geometry->thermal
                                                        : c.imported                        ? &c.imported->thermal
                                                                                            : nullptr;
                       if (thermal)
                         for (const auto& w : thermal->warnings) std::cerr << "radnet: warning: " << w << "\n";
                       std::cout << path << ": valid (" << c.nodeCount() << " nodes";
                       if (c.geometry) {  // cases/config/work_estimate.hpp
                         const WorkEstimate w = estimateWork(*c.geometry);
                         std::cout << "; about " << std::setprecision(3) << w.total() / 1e9 << " GB of memory, "
                                   << (w.sparse ? "sparse" : "dense") << " matrices: "
                                   << std::setprecision(2) << 100.0 * w.facing_share << " % of node pairs face each other";
                         if (w.configurations > 0)
                           std::cout << "; " << w.configurations << " configurations of the turning parts";
                       }
                       std::cout << ")\n";
                       return 0;
                     }));
  return worst;
}

}  // namespace radnet::cases
