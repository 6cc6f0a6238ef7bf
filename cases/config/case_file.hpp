#pragma once
// A case file of one of three forms: the network given directly (`network:`), geometry with
// computed view factors (`geometry:`), or a thermal network imported from another tool (`import:`). Schema in docs/case-files.md.
#include "cases/config/geometry_case.hpp"
#include "cases/config/import_case.hpp"
#include "cases/config/network_case.hpp"

#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

struct LoadedCase {
  std::optional<NetworkCase> network;
  std::optional<GeometryCase> geometry;
  std::optional<ImportedCase> imported;
  size_t nodeCount() const {
    return network ? network->names.size() : imported ? imported->thermal.node_names.size() : geometry->node_names.size();
  }
  const std::vector<Expectation>& expectations() const {
    return network ? network->expectations : imported ? imported->expectations : geometry->expectations;
  }
};

/// Reads, parses and validates the case file at `path`.
/// @throws InputError with file:line:column
LoadedCase loadCase(const std::string& path);

}  // namespace radnet::cases
