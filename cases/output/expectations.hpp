#pragma once
// `radnet check`: the computed value each expectation names, and the PASS/FAIL report.
#include "cases/config/expectation.hpp"
#include "cases/pipeline/results.hpp"

#include <functional>
#include <iosfwd>
#include <optional>
#include <vector>

namespace radnet::cases {

/// The computed value of an expectation; empty when the run has no such result.
std::optional<double> lookupResult(const NetworkRunResult& r, const Expectation& x);
std::optional<double> lookupResult(const ImportRunResult& r, const Expectation& x);
std::optional<double> lookupResult(const GeometryRunResult& r, const Expectation& x);

using ResultLookup = std::function<std::optional<double>(const Expectation&)>;

/// Prints one line per expectation; returns the number that failed.
int evaluateExpectations(const std::vector<Expectation>& expectations, const ResultLookup& lookup, std::ostream& out);

}  // namespace radnet::cases
