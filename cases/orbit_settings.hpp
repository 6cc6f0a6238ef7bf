#pragma once
// The `orbit`, `attitude` and `environment` keys of a case (schema in docs/case-files.md).
#include "cases/yaml_support.hpp"
#include "orbits/attitude.hpp"
#include "orbits/loads.hpp"
#include "orbits/orbit.hpp"
#include "orbits/sweep.hpp"

#include <memory>
#include <optional>
#include <string>

namespace radnet::cases {

struct OrbitSettings {
  std::unique_ptr<orbits::Orbit> orbit;
  std::string description;  ///< how the orbit was defined, for the summary
  orbits::AttitudeSpec attitude;
  orbits::SweepOptions sweep;
  orbits::EnvironmentOptions environment;
};

/// Parses `orbit:` (with `attitude:` and `environment:`); nullopt when the case has no orbit.
/// @throws InputError with file:line:column
std::optional<OrbitSettings> parseOrbitSettings(const YamlDocument& doc);

}  // namespace radnet::cases
