#include "cases/config/output_settings.hpp"

namespace radnet::cases {

OutputSettings parseOutputSettings(const YamlDocument& doc, const YAML::Node& root) {
  OutputSettings s;
  const YAML::Node out = root["output"];
  if (!out) return s;
  doc.expectMap(out, "output", {"dense_matrices", "dense_exchange_factors"});
  if (out["dense_matrices"]) s.dense_matrices = doc.boolean(out["dense_matrices"], "output.dense_matrices");
  if (out["dense_exchange_factors"])
    s.dense_exchange_factors = doc.boolean(out["dense_exchange_factors"], "output.dense_exchange_factors");
  return s;
}

}  // namespace radnet::cases
