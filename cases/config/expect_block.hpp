#pragma once
// The `expect:` block of a case (docs/case-files.md).
#include "cases/config/expectation.hpp"
#include "cases/config/yaml_document.hpp"

#include <string>
#include <vector>

namespace radnet::cases {

/// Parses `expect:` (a sequence of {quantity, node, to, index, value, tolerance}) against
/// the case's node names: radiative quantities name radiative nodes, temperatures any
/// thermal node (lumped ones too). @throws InputError with file:line:column
/// @param case_names  the design cases (geometry form): `case:` names one, and orbit
///                    quantities and `index` then refer to its positions (default the first)
std::vector<Expectation> parseExpectations(const YamlDocument& doc, const YAML::Node& node,
                                           const std::vector<std::string>& radiative_names,
                                           const std::vector<std::string>& thermal_names,
                                           const std::vector<std::string>& case_names = {});

}  // namespace radnet::cases
