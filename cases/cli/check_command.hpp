#pragma once
// `radnet check CASE...`: runs every case that has an `expect:` block and compares its
// results with the expectations (docs/cli.md); writes no file.
#include "cases/cli/read_commands.hpp"  // Guard

#include <string>
#include <vector>

namespace radnet::cases {

/// Exit code: 0 all passed, 1 a check failed, 2 no case had an `expect:` block (or a case
/// was malformed), the worst of the cases' codes otherwise.
int checkCommand(const std::vector<std::string>& paths, const Guard& guarded);

}  // namespace radnet::cases
