#pragma once
// The `orbit`, `attitude` and `environment` keys of a case (schema in docs/case-files.md).
#include "cases/config/yaml_document.hpp"
#include "orbits/attitude.hpp"
#include "orbits/loads.hpp"
#include "orbits/orbit.hpp"
#include "orbits/sweep.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace radnet::cases {

/// One orbit of a case; several when `epoch` or `beta` is a list (seasons, beta sweeps,
/// hot and cold cases), one per combination.
struct OrbitCase {
  std::unique_ptr<orbits::Orbit> orbit;
  std::string label;  ///< e.g. "epoch 2026-06-21T00:00:00Z, beta 60°"
};

struct OrbitSettings {
  std::vector<OrbitCase> cases;
  const orbits::CentralBody* body = &orbits::CentralBody::earth();  ///< `orbit.body`
  std::string description;  ///< how the orbit was defined, for the summary
  orbits::AttitudeSpec attitude;
  orbits::SweepOptions sweep;
  orbits::EnvironmentOptions environment;
};

/// Parses `orbit:` (with `attitude:` and `environment:`); nullopt when the case has no orbit.
/// @throws InputError with file:line:column
std::optional<OrbitSettings> parseOrbitSettings(const YamlDocument& doc);

/// The same from the given `orbit`, `attitude` and `environment` mappings (a design case's,
/// merged over the base case's; any may be undefined).
std::optional<OrbitSettings> parseOrbitSettings(const YamlDocument& doc, const YAML::Node& orbit,
                                                const YAML::Node& attitude, const YAML::Node& environment);

/// Parses `attitude:` (nadir when absent).
orbits::AttitudeSpec parseAttitude(const YamlDocument& doc, const YAML::Node& node);

/// Parses `environment:` into the sweep's solar constant and the loads' options; what it
/// leaves unsaid (albedo, planet IR) is the central body's.
void parseEnvironment(const YamlDocument& doc, const YAML::Node& node, const orbits::CentralBody& body,
                      orbits::SweepOptions& sweep, orbits::EnvironmentOptions& environment);

}  // namespace radnet::cases
