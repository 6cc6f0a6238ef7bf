#include "cases/output/tmd_export.hpp"

#include "cases/config/errors.hpp"
#include "cases/config/esatan_tmd.hpp"
#include "cases/output/hdf5_reader.hpp"
#include "cases/output/hdf5_writer.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::cases {
namespace {

constexpr double kStefanBoltzmann = 5.670374419e-8;  // W/(m² K⁴), CODATA 2018, as the decks use
constexpr double kCelsiusOffset = 273.15;           // K: ESATAN's TAbs
constexpr size_t kEsatanStringWidth = 24;            // ESATAN's node types and labels are S24

// Each node's area-weighted centroid (m) from /geometry; lumped nodes and results without
// geometry at 0, as ESATAN writes nodes without a shape.
Eigen::MatrixXd centroids(const Hdf5Reader& h5, Eigen::Index n) {
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, 3);
  if (!h5.has("/geometry/triangle_node") || !h5.has("/geometry/vertices") || !h5.has("/geometry/triangles")) return c;
  const Eigen::MatrixXd v = h5.matrix("/geometry/vertices"), tri = h5.matrix("/geometry/triangles");
  const Eigen::VectorXd node = h5.vector("/geometry/triangle_node");
  if (v.cols() != 3 || tri.cols() != 3 || tri.rows() != node.size() || !v.allFinite())
    throw InputError(h5.path(), 0, 0, "/geometry: vertices, triangles and triangle_node disagree (a damaged result)");
  Eigen::VectorXd area = Eigen::VectorXd::Zero(n);
  for (Eigen::Index k = 0; k < tri.rows(); ++k) {
    Eigen::Vector3d p[3];
    for (int s = 0; s < 3; ++s) {
      const double index = tri(k, s);
      if (!(index >= 0 && index < static_cast<double>(v.rows())))
        throw InputError(h5.path(), 0, 0, "/geometry/triangles: a vertex index outside /geometry/vertices");
      p[s] = v.row(static_cast<Eigen::Index>(index)).transpose();
    }
    if (!(node[k] >= 0 && node[k] < static_cast<double>(n))) continue;  // an inactive triangle
    const auto i = static_cast<Eigen::Index>(node[k]);
    const double a = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).norm();
    c.row(i) += a * (p[0] + p[1] + p[2]).transpose() / 3.0, area[i] += a;
  }
  for (Eigen::Index i = 0; i < n; ++i)
    if (area[i] > 0) c.row(i) /= area[i];
  return c;
}

// Incident power at every position of the case (n × P), W: the irradiance times the area.
Eigen::MatrixXd incident(const Hdf5Reader& h5, const char* path, const ExportedNetwork& net) {
  const auto n = static_cast<Eigen::Index>(net.nodes.size());
  const Eigen::Index P = net.case_end - net.case_first;
  if (!h5.has(path)) return Eigen::MatrixXd::Zero(n, P);
  const Eigen::MatrixXd m = h5.matrix(path);  // (P_all, n_radiative)
  if (m.rows() < net.case_end || m.cols() > n || !m.allFinite())
    throw InputError(h5.path(), 0, 0, std::string(path) + ": not one finite row per position (a damaged result)");
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, P);
  out.topRows(m.cols()) = m.middleRows(net.case_first, P).transpose();
  return out.array().colwise() * net.area_m2.array();
}

// /AnalysisSet1: the nodes, the names of their real attributes and the conductor pairs.
void writeTables(Hdf5Writer& out, const ExportedNetwork& net) {
  const int n = static_cast<int>(net.nodes.size());
  Eigen::MatrixXi nodes(n + 1, 2);
  for (int i = 0; i <= n; ++i) nodes.row(i) << deckNodeNumber(net, i), 1;  // model 1: radnet's only model
  out.writeIntegers("/AnalysisSet1/thermalNodes", nodes, "1");
  out.writeFixedStrings("/AnalysisSet1/thermalNodesRealAttributes", {16},
                        std::vector<std::string>(kTmdRealAttributes.begin(), kTmdRealAttributes.end()), 32);
  out.writeFixedStrings("/AnalysisSet1/thermalNodesStringAttributes", {2}, {"Type", "Label"}, 32);
  for (const auto* list : {&net.gl, &net.gr}) {
    Eigen::MatrixXi pairs(static_cast<Eigen::Index>(list->size()), 4);
    for (size_t k = 0; k < list->size(); ++k)  // 1-based rows of thermalNodes, then each node's model
      pairs.row(static_cast<Eigen::Index>(k)) << (*list)[k].i + 1, (*list)[k].j + 1, 1, 1;
    out.writeIntegers(list == &net.gl ? "/AnalysisSet1/conductorsGL" : "/AnalysisSet1/conductorsGR", pairs, "1");
  }
  out.attribute("/AnalysisSet1", "StefanBoltzmann", kStefanBoltzmann);
  out.attribute("/AnalysisSet1", "TAbs", kCelsiusOffset);
  out.fixedStringAttribute("/AnalysisSet1", "Description", net.name);
}

}  // namespace

void writeTmdExport(const Hdf5Reader& h5, const ExportOptions& o, const std::string& path) {
  const ExportedHistory history = readExportedHistory(h5, o);
  const ExportedNetwork& first = history.at.front();
  if (!first.thermal)
    throw InputError(h5.path(), 0, 0, "the result has no temperatures (its case has no thermal: block), and a TMD "
                                      "holds them at every time: export --format esatan, sinda or csv for its loads");
  const std::vector<double>& times = history.times_s;
  const int n = static_cast<int>(first.nodes.size()), N = n + 1;
  const Eigen::Index M_gl = static_cast<Eigen::Index>(first.gl.size()), M_gr = static_cast<Eigen::Index>(first.gr.size());
  const Eigen::MatrixXd xyz = centroids(h5, n);
  const Eigen::MatrixXd in_solar = incident(h5, "/loads/incident_solar", first);
  const Eigen::MatrixXd in_albedo = incident(h5, "/loads/incident_albedo", first);
  const Eigen::MatrixXd in_earth = incident(h5, "/loads/incident_earth_ir", first);
  std::vector<Eigen::MatrixXd> real, gl, gr;
  std::vector<std::string> text;
  for (size_t k = 0; k < history.at.size(); ++k) {
    const ExportedNetwork& net = history.at[k];
    Eigen::MatrixXd r = Eigen::MatrixXd::Zero(N, 16);
    for (int i = 0; i < n; ++i) {
      const bool fixed = std::isfinite(net.fixed_temperature_k[i]);
      r(i, kTmdTemperature) = net.temperature_k[i] - kCelsiusOffset;  // a boundary node's held value (it may follow a history)
      r(i, kTmdCapacitance) = fixed ? 0.0 : net.capacitance_j_k[i];
      r(i, kTmdAlbedo) = net.q_albedo_w[i], r(i, kTmdEarth) = net.q_earth_ir_w[i];
      r(i, kTmdInternal) = net.q_internal_w[i], r(i, kTmdSolar) = net.q_solar_w[i];
      r(i, kTmdArea) = net.area_m2[i], r(i, kTmdAbsorptivity) = net.absorptivity[i];
      r(i, kTmdEmissivity) = net.emissivity[i];
      const auto p = static_cast<Eigen::Index>(k);
      r(i, kTmdIncidentAlbedo) = in_albedo(i, p), r(i, kTmdIncidentEarth) = in_earth(i, p);
      r(i, kTmdIncidentSolar) = in_solar(i, p);
      r.block(i, kTmdX, 1, 3) = xyz.row(i);
      text.push_back(fixed ? "B" : "D"), text.push_back(net.nodes[static_cast<size_t>(i)]);
    }
    r(n, kTmdTemperature) = net.space_temperature_k - kCelsiusOffset;
    text.push_back("B"), text.push_back("SPACE");
    real.push_back(r);
    Eigen::MatrixXd g(M_gl, 2), q(M_gr, 2);
    for (Eigen::Index c = 0; c < M_gl; ++c) g.row(c) << net.gl[static_cast<size_t>(c)].value, 1.0;
    for (Eigen::Index c = 0; c < M_gr; ++c) q.row(c) << first.gr[static_cast<size_t>(c)].value, 1.0;  // one optical set
    gl.push_back(g), gr.push_back(q);
  }
  size_t width = kEsatanStringWidth;
  for (const std::string& s : first.nodes) width = std::max(width, s.size());  // a longer name is not cut
  Hdf5Writer out(path);
  out.fixedStringAttribute("/", "FileVersion", "01.00");
  out.fixedStringAttribute("/", "Description", first.name);
  writeTables(out, first);
  const std::string data = "/AnalysisSet1/DataGroup1";
  out.writeVector(data + "/times", Eigen::Map<const Eigen::VectorXd>(times.data(), static_cast<Eigen::Index>(times.size())), "s");
  out.writeStack(data + "/thermalNodesRealData", real, "SI; Temperature in degC");
  out.writeFixedStrings(data + "/thermalNodesStringData", {times.size(), static_cast<unsigned long long>(N), 2}, text, width);
  out.writeStack(data + "/conductorDataGL", gl, "W/K");
  out.writeStack(data + "/conductorDataGR", gr, "m^2");
  out.fixedStringAttribute(data, "Description", "radnet " + (first.design_case.empty() ? std::string("run") : "design case " + first.design_case));
  out.commit();
}

}  // namespace radnet::cases
