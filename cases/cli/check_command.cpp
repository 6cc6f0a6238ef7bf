#include "cases/cli/check_command.hpp"

#include "cases/config/case_file.hpp"
#include "cases/output/expectations.hpp"
#include "cases/pipeline/distributed.hpp"
#include "cases/pipeline/geometry_run.hpp"
#include "cases/pipeline/network_run.hpp"

#include <algorithm>
#include <iostream>
#include <sstream>

namespace radnet::cases {
namespace {

constexpr int kExitCheckFailed = 1;
constexpr int kExitBadInput = 2;

// One case of `radnet check`: runs it when it has an `expect:` block; counts failures.
int checkCase(const std::string& path, int& checked, int& failed_total) {
  const LoadedCase c = loadCase(path);
  checkSameCase(path, c);  // under MPI: every rank read the same files
  std::cout << "== " << path << "\n";
  if (c.expectations().empty()) {
    std::cout << "SKIP (no 'expect:' block)\n";
    return 0;
  }
  ++checked;
  std::ostringstream sink;
  int failed = 0;
  if (c.network) {
    const NetworkRunResult r = runNetworkCase(*c.network, sink);
    failed = evaluateExpectations(
        c.expectations(), [&](const Expectation& x) { return lookupResult(r, x); }, std::cout);
  } else if (c.imported) {
    const ImportRunResult r = runImportedCase(*c.imported, sink);
    failed = evaluateExpectations(
        c.expectations(), [&](const Expectation& x) { return lookupResult(r, x); }, std::cout);
  } else {
    const GeometryRunResult r = runGeometryCase(*c.geometry, false, sink);
    failed = evaluateExpectations(
        c.expectations(), [&](const Expectation& x) { return lookupResult(r, x); }, std::cout);
  }
  failed_total += failed;
  return failed ? kExitCheckFailed : 0;
}

}  // namespace

// Every case runs; the worst outcome decides the exit code.
int checkCommand(const std::vector<std::string>& paths, const Guard& guarded) {
  int worst = 0, failed_total = 0, checked = 0;
  for (const auto& path : paths)
    worst = std::max(worst, guarded([&] { return checkCase(path, checked, failed_total); }));
  if (checked == 0 && worst == 0) {
    std::cerr << "radnet check: none of the cases has an 'expect:' block: nothing was checked\n";
    return kExitBadInput;
  }
  std::cout << (failed_total == 0 && worst == 0 ? "all checks passed" : "checks FAILED") << " (" << checked
            << " case(s) checked)\n";
  return worst;
}

}  // namespace radnet::cases
