#pragma once
// Design cases of a geometry case (docs/case-files.md, "Design cases"): named optical sets
// (`optics:`, e.g. end-of-life coatings), named cases (`cases:`, e.g. hot and cold) that
// override the base case's orbit, attitude, environment, optics and dissipations, and an
// optional sampling of the optical properties (`uncertainty:`). All of them share the one
// geometry, its view factors and its one eigendecomposition.
#include "cases/config/orbit_settings.hpp"
#include "geometry/rays/specular.hpp"

#include <Eigen/Dense>

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace radnet::cases {

/// The optical properties of every radiative node under one named set; `base` is the
/// materials as given.
struct OpticalSet {
  std::string name;
  /// Per radiative node, –: the network's ε/κ, α/κ where a surface is specular or
  /// transmissive (GeometryCase::emissivity), else the materials' values.
  Eigen::VectorXd emissivity, absorptivity;
  Eigen::VectorXd surface_emissivity, surface_absorptivity;  ///< the surfaces' own, –
  /// The set's ρs and τ per node in each band (empty: no surface redirects in this set).
  geometry::SpecularBand specular_ir, specular_solar;
  /// Its ρs or τ differ from the base case's somewhere: the set has networks of its own,
  /// traced with its optics and solved without a decomposition of their own (docs/solver.md).
  bool own_specular = false;
};

/// One design case: the base case with some blocks overridden.
struct DesignCase {
  std::string name;
  int optics = 0;                      ///< index into GeometryCase::optical_sets
  std::optional<OrbitSettings> orbit;  ///< the base orbit with the case's overrides; absent: no orbit
  double dissipation_scale = 1.0;      ///< multiplies every constant and scheduled dissipation, –
  std::vector<std::pair<int, double>> dissipation;  ///< (thermal node, W): constant, replacing any schedule
  /// The case's orbit, attitude and environment blocks, canonical, without the solar
  /// constant, a constant albedo and the Earth IR: two cases that share it have the same
  /// incident irradiances up to those three factors, so the later reuses the earlier's.
  std::string load_signature;
};

/// `uncertainty:` the materials' α and ε drawn independently (normal, 1σ absolute, clipped
/// to [0, 1]), every sample on the same eigendecomposition.
struct OpticalUncertainty {
  double absorptivity_sigma = 0.0;  ///< –
  double emissivity_sigma = 0.0;    ///< –
  int samples = 64;
  std::uint64_t seed = 1;
};

struct GeometryCase;

/// Parses `optics:` into c.optical_sets (base first). Needs the materials and node materials.
/// @throws InputError with file:line:column
void parseOpticalSets(const YamlDocument& doc, GeometryCase& c);

/// Parses `cases:` (or makes the one case `base`) with their orbits, into c.design_cases.
void parseDesignCases(const YamlDocument& doc, GeometryCase& c);

/// Parses the cases' `dissipation_scale` and `dissipation` once the thermal model is known.
void parseCaseDissipations(const YamlDocument& doc, GeometryCase& c);

/// Parses `uncertainty:` into c.optical_uncertainty.
void parseOpticalUncertainty(const YamlDocument& doc, GeometryCase& c);
/// `limits: {node: [min_K, max_K]}` (needs `thermal`; min < max, both within the thermal range).
void parseLimits(const YamlDocument& doc, GeometryCase& c);

/// The names a design case or optical set may have: letters, digits, '_', '-' and '.',
/// starting with a letter, a digit or '_' (they become HDF5 group names and labels).
bool isCaseName(const std::string& name);

}  // namespace radnet::cases
