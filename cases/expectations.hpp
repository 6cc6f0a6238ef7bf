#pragma once
// The `expect:` block of a case: analytic values with tolerances that `radnet check`
// compares against a run's results (CI for users' models).
#include "cases/network_case.hpp"

#include <functional>
#include <iosfwd>
#include <optional>
#include <vector>

namespace radnet::cases {

/// Parses `expect:` (a sequence of {quantity, node, to, index, value, tolerance}).
std::vector<Expectation> parseExpectations(const YamlDocument& doc, const YAML::Node& node,
                                           const std::vector<std::string>& node_names);

/// Looks up the computed value of an expectation; empty when the run has no such result.
using ResultLookup = std::function<std::optional<double>(const Expectation&)>;

/// Prints one line per expectation; returns the number that failed.
int evaluateExpectations(const std::vector<Expectation>& expectations, const ResultLookup& lookup,
                         std::ostream& out);

}  // namespace radnet::cases
