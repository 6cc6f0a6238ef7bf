#include "cases/output/result_files.hpp"

#include "cases/output/hdf5_layout.hpp"
#include "cases/output/xdmf.hpp"

#include <filesystem>

namespace radnet::cases {

void writeNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const std::string& path) {
  Hdf5Writer h5(path);
  writeMeta(h5, c.name, c.yaml_text);
  writeRadiativeNetwork(h5, r.radiative);
  h5.writeVector("/nodes/reflectance", c.reflectance, "1");
  h5.writeVector("/nodes/initial_exitance", c.initial_exitance, "W/m^2");
  if (c.emissivity) h5.writeVector("/nodes/emissivity", *c.emissivity, "1");
  h5.writeVector("/solution/exitance", r.solution.exitance.col(0), "W/m^2");
  h5.writeVector("/solution/irradiance", r.solution.irradiance.col(0), "W/m^2");
  if (r.thermal) writeTemperatures(h5, *r.thermal, *r.heat, *c.thermal, nullptr);
  writeTimings(h5, r.timings);
  h5.attribute("/report", "truncation_residual", r.solution.max_residual);
  h5.attribute("/report", "refined", static_cast<long long>(r.solution.refined));
  h5.attribute("/report", "refine_iterations", static_cast<long long>(r.solution.refine_iterations));
  h5.attribute("/report", "view_factor_error", r.radiative.network->reciprocity().max_view_factor_change);
  h5.commit();
}

void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, const std::string& path) {
  Hdf5Writer h5(path);
  writeMeta(h5, c.name, c.yaml_text, c.included);
  writeRadiativeNetwork(h5, r.radiative);
  h5.writeVector("/nodes/emissivity", c.emissivity, "1");
  h5.writeVector("/nodes/absorptivity", c.absorptivity, "1");
  h5.writeStrings("/nodes/material", c.node_material);
  writeGeometry(h5, c.scene, r.triangle_node);
  writeViewFactorEstimate(h5, r, c.view_factors.method);
  if (r.sweep) writeSweep(h5, *r.sweep);
  if (r.thermal) writeTemperatures(h5, *r.thermal, *r.heat, *c.thermal, r.sweep ? &*r.sweep : nullptr);
  const std::vector<XdmfAttribute> cell_values = writeXdmfCellValues(h5, r);
  writeTimings(h5, r.timings);
  std::vector<double> times;
  if (r.sweep)
    for (const auto& p : r.sweep->positions) times.push_back(p.t_s);
  const std::string text =
      xdmfText(std::filesystem::path(path).filename().string(), static_cast<long>(c.scene.vertexMatrix().rows()),
               static_cast<long>(c.scene.faces().size()), times, cell_values);
  h5.commit();
  writeTextAtomically(xdmfPathFor(path), text);
}

}  // namespace radnet::cases
