#pragma once
// The commands that read and compute nothing: `radnet validate CASE...` and
// `radnet report RESULT.h5 [-o DIR] [--limits FILE]` (docs/radnet_report.py run with Debian's
// python3; its exit code is radnet's: 0, 2 a malformed result or bad limits, 4 not written).
#include <functional>
#include <string>
#include <vector>

namespace radnet::cases {

/// Runs a command's body, mapping its exceptions to exit codes (main.cpp's `guarded`).
using Guard = std::function<int(const std::function<int()>&)>;

int validateCommand(const std::vector<std::string>& paths, const Guard& guarded);

int reportCommand(const std::string& result, std::string dir, const std::string& limits);

}  // namespace radnet::cases
