#include "cases/output/result_files.hpp"

#include "cases/config/errors.hpp"
#include "cases/output/hdf5_layout.hpp"
#include "cases/output/shared_matrices.hpp"
#include "cases/output/xdmf.hpp"

#include <cstdio>
#include <filesystem>

namespace radnet::cases {

void writeNetworkResult(const NetworkCase& c, const NetworkRunResult& r, const std::string& path,
                        const std::vector<std::string>& warnings) {
  Hdf5Writer h5(path);
  writeMeta(h5, c.name, c.yaml_text);
  writeNodes(h5, r.radiative, r.thermal);
  writeRadiativeNetwork(h5, r.radiative, c.output);
  const Eigen::Index n = nodeCount(r.radiative, r.thermal);
  h5.writeVector("/nodes/reflectance", padNodes(c.reflectance, n).col(0), "1");
  h5.writeVector("/nodes/initial_exitance", padNodes(c.initial_exitance, n).col(0), "W/m^2");
  if (c.emissivity) h5.writeVector("/nodes/emissivity", padNodes(*c.emissivity, n).col(0), "1");
  h5.writeVector("/solution/exitance", r.solution.exitance.col(0), "W/m^2");
  h5.writeVector("/solution/irradiance", r.solution.irradiance.col(0), "W/m^2");
  if (r.thermal) writeTemperatures(h5, *r.thermal, *c.thermal, nullptr);
  writeTimings(h5, r.timings);
  h5.attribute("/report", "truncation_residual", r.solution.max_residual);
  h5.attribute("/report", "refined", static_cast<long long>(r.solution.refined));
  h5.attribute("/report", "refine_iterations", static_cast<long long>(r.solution.refine_iterations));
  h5.attribute("/report", "band_method", r.solution.method);
  h5.attribute("/report", "view_factor_error", r.radiative.network->reciprocity().max_view_factor_change);
  h5.writeStrings("/report/warnings", warnings);
  h5.commit();
}

void writeImportedResult(const ImportedCase& c, const ImportRunResult& r, const std::string& path,
                         const std::vector<std::string>& warnings) {
  Hdf5Writer h5(path);
  writeMeta(h5, c.name, c.yaml_text);
  h5.attribute("/meta", "imported_from", c.source);
  const Eigen::Index n = c.thermal.nodeCount();
  h5.writeStrings("/nodes/name", c.thermal.node_names);
  h5.writeStrings("/nodes/label", c.labels);
  h5.writeVector("/nodes/area", Eigen::VectorXd::Zero(n), "m^2");  // no surface of radnet's: GR came with the file
  h5.writeBooleans("/nodes/lumped", std::vector<bool>(static_cast<size_t>(n), true));
  writeTemperatures(h5, r.thermal, c.thermal, nullptr);
  h5.attribute("/solution/time", "origin", std::string("the imported file's times"));
  writeTimings(h5, r.timings);
  h5.writeStrings("/report/warnings", warnings);
  h5.commit();
}

void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, const std::string& path,
                         const std::vector<std::string>& warnings) {
  Hdf5Writer h5(path);
  writeGeometryResult(c, r, h5, path, warnings);
}

RawEstimateWriter rawEstimateInto(Hdf5Writer& h5) {
  return [&h5](const geometry::ViewFactorEstimate& raw, bool dense) { writeRawViewFactors(h5, raw, dense); };
}

void writeGeometryResult(const GeometryCase& c, const GeometryRunResult& r, Hdf5Writer& h5, const std::string& path,
                         const std::vector<std::string>& warnings) {
  writeMeta(h5, c.name, c.yaml_text, c.included);
  writeNodes(h5, r.radiative, r.thermal);
  writeRadiativeNetwork(h5, r.radiative, c.output);
  const Eigen::Index n = nodeCount(r.radiative, r.thermal);
  h5.writeVector("/nodes/emissivity", padNodes(c.surface_emissivity, n).col(0), "1");
  h5.writeVector("/nodes/absorptivity", padNodes(c.surface_absorptivity, n).col(0), "1");
  std::vector<std::string> material = c.node_material;
  material.resize(static_cast<size_t>(n));  // lumped nodes: no surface, no material
  h5.writeStrings("/nodes/material", material);
  writeGeometry(h5, c.scene, c.seams, r.triangle_node);
  writeViewFactorEstimate(h5, r, c.view_factors.method, c.output);
  if (r.sweep) writeSweep(h5, *r.sweep, n);
  if (r.thermal) writeTemperatures(h5, *r.thermal, *c.thermal, r.sweep ? &*r.sweep : nullptr);
  writeUncertainty(h5, c, r, n);
  writeDesignCases(h5, c, r);
  writeArticulation(h5, c, r);
  if (r.optical_uncertainty) writeOpticalUncertainty(h5, c, *r.optical_uncertainty);
  if (!c.limits.empty()) {
    std::vector<std::string> node;
    Eigen::VectorXd lo(static_cast<Eigen::Index>(c.limits.size())), hi(lo.size());
    for (size_t k = 0; k < c.limits.size(); ++k) {
      node.push_back(c.thermal->node_names[static_cast<size_t>(c.limits[k].node)]);
      lo[static_cast<Eigen::Index>(k)] = c.limits[k].min_k, hi[static_cast<Eigen::Index>(k)] = c.limits[k].max_k;
    }
    h5.writeStrings("/limits/node", node);
    h5.writeVector("/limits/min", lo, "K");
    h5.writeVector("/limits/max", hi, "K");
  }
  const XdmfPlan xdmf = writeXdmfData(h5, c.scene, r, path);
  writeSharedMatrices(&h5, r);  // rows shared out over MPI ranks: the other ranks join each block
  writeTimings(h5, r.timings);
  h5.writeStrings("/report/warnings", warnings);
  h5.commit(xdmfFiles(xdmf, path));  // the result and its ParaView files, or neither
}

}  // namespace radnet::cases
