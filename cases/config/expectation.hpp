#pragma once
// One entry of a case's `expect:` block: an analytic value with a tolerance that
// `radnet check` compares against the run's result (CI for users' models).
#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace radnet::cases {

/// The quantities an expectation may name; spelled once, in kExpectQuantityNames.
enum class ExpectQuantity {
  Exitance,               ///< M of a node, W/m² (network form)
  Irradiance,             ///< H of a node, W/m² (network form)
  ViewFactor,             ///< F from `node` to `to`, –
  SpaceViewFactor,        ///< F_space of a node, –
  RadiativeExchange,      ///< GR from `node` to `to`, m²
  GrSpace,                ///< GR to space of a node, m²
  Eigenvalue,             ///< λ number `index` (0-based, by decreasing |λ|), m²
  Temperature,            ///< T of a node at position `index` (default 0), K
  OrbitMeanAbsorbed,      ///< orbit mean of the absorbed environmental power, W
  OrbitMaxAbsorbedSolar,  ///< orbit maximum of the absorbed direct solar power, W
};

/// Case-file spelling of each quantity, in enum order.
inline constexpr std::array<std::string_view, 10> kExpectQuantityNames = {
    "exitance", "irradiance", "view_factor", "space_view_factor",   "radiative_exchange",
    "gr_space", "eigenvalue", "temperature", "orbit_mean_absorbed", "orbit_max_absorbed_solar"};

inline std::string_view toString(ExpectQuantity q) { return kExpectQuantityNames[static_cast<size_t>(q)]; }

/// The quantity spelled `word`, if any.
inline std::optional<ExpectQuantity> expectQuantity(std::string_view word) {
  for (size_t k = 0; k < kExpectQuantityNames.size(); ++k)
    if (kExpectQuantityNames[k] == word) return static_cast<ExpectQuantity>(k);
  return std::nullopt;
}

/// True for quantities between two nodes (they need `to`).
inline bool isPairQuantity(ExpectQuantity q) {
  return q == ExpectQuantity::ViewFactor || q == ExpectQuantity::RadiativeExchange;
}

struct Expectation {
  ExpectQuantity quantity = ExpectQuantity::Exitance;
  std::string node;  ///< node name (empty for eigenvalue)
  std::string to;    ///< second node for pair quantities
  int index = -1;    ///< eigenvalue index or sweep position (-1: not given)
  double value = 0.0;
  double tolerance = 0.0;  ///< absolute
  std::string where;       ///< file:line:column of the entry, for messages
  int design_case = 0;     ///< `case:` (geometry form): whose positions orbit quantities and indices refer to
  bool case_given = false;
};

}  // namespace radnet::cases
