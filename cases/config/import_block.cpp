#include "cases/config/import_case.hpp"

#include "cases/config/damaged_file_guard.hpp"
#include "cases/config/errors.hpp"
#include "cases/config/expect_block.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

namespace radnet::cases {
namespace {

// The thermal model's ranges (docs/case-files.md, "Ranges"): an imported value beyond them
// is refused as a typed one would be.
constexpr double kMaxPower = 1e9, kMaxConductance = 1e12, kMaxCapacitance = 1e12, kMaxCoupling = 1e9;
constexpr double kMinTemperature = 1e-3, kMaxTemperature = 1e5;  // K
// How far a value may move between output times and still be taken as constant: ESATAN
// writes 15 significant digits, so anything beyond round-off is a real change.
constexpr double kConstantRelative = 1e-9;

bool varies(const Eigen::Ref<const Eigen::VectorXd>& v, double scale) {
  return v.size() > 1 && (v.maxCoeff() - v.minCoeff()) > kConstantRelative * std::max(scale, v.cwiseAbs().maxCoeff());
}

std::string nodeName(const TmdFile& f, Eigen::Index i) {
  return f.type[static_cast<size_t>(i)] + std::to_string(f.node_number[static_cast<size_t>(i)]);
}

Eigen::VectorXd column(const TmdFile& f, Eigen::Index i, int attribute) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(f.times_s.size()));
  for (size_t t = 0; t < f.times_s.size(); ++t) v[static_cast<Eigen::Index>(t)] = f.real[t](i, attribute);
  return v;
}

// Node k of the model (row i of the file): capacitance, boundary or initial temperature, heat sources.
void importNode(const TmdFile& f, const std::string& path, Eigen::Index i, Eigen::Index k, ThermalSettings& s,
                std::vector<std::string>& warnings) {
  const std::string name = nodeName(f, i);
  const auto bad = [&](const std::string& what) { throw InputError(path, 0, 0, "node " + name + ": " + what); };
  const Eigen::VectorXd t_k = column(f, i, kTmdTemperature).array() + f.celsius_offset_k;
  if (!(t_k.minCoeff() >= kMinTemperature && t_k.maxCoeff() <= kMaxTemperature))
    bad("temperature " + std::to_string(t_k.minCoeff()) + " K, outside " + std::to_string(kMinTemperature) + " … 1e5 K");
  const Eigen::VectorXd c = column(f, i, kTmdCapacitance);
  if (c[0] < 0 || c[0] > kMaxCapacitance) bad("capacitance " + std::to_string(c[0]) + " J/K, outside 0 … 1e12");
  if (f.type[static_cast<size_t>(i)] == "B") {  // held at the file's temperature, following it in time
    s.fixed_temperature[k] = t_k[0];
    if (varies(t_k, 1.0)) {
      solver::BoundarySchedule b;
      b.node = static_cast<int>(k);
      for (size_t t = 0; t < f.times_s.size(); ++t)
        b.times_s.push_back(f.times_s[t] - f.times_s[0]), b.temperature_k.push_back(t_k[static_cast<Eigen::Index>(t)]);
      s.boundary_schedules.push_back(b);
    }
    return;
  }
  s.capacitance[k] = c[0];
  if (varies(c, 0.0))
    warnings.push_back("import: node " + name + "'s capacitance changes during the file's run (" +
                       std::to_string(c.minCoeff()) + " … " + std::to_string(c.maxCoeff()) +
                       " J/K, temperature-dependent?): the first time's value is used throughout");
  s.initial_temperature[k] = t_k[0];
  Eigen::VectorXd q = Eigen::VectorXd::Zero(t_k.size());
  for (int a : {kTmdSolar, kTmdAlbedo, kTmdEarth, kTmdInternal, kTmdRest}) q += column(f, i, a);
  if (!(q.cwiseAbs().maxCoeff() <= kMaxPower)) bad("a heat source beyond 1e9 W");
  if (!varies(q, 0.0)) {
    s.dissipation[k] = q[0];
    return;
  }
  solver::DissipationSchedule sch;
  sch.node = static_cast<int>(k);
  sch.kind = solver::DissipationSchedule::Kind::Interpolated;
  for (size_t t = 0; t < f.times_s.size(); ++t)
    sch.times_s.push_back(f.times_s[t] - f.times_s[0]), sch.power_w.push_back(q[static_cast<Eigen::Index>(t)]);
  s.schedules.push_back(sch);
}

// GL (W/K) or GR (m²) between active nodes at the first time, both directions; a conductor
// touching an inactive node is dropped, as ESATAN drops it.
void importConductors(const TmdConductors& c, const std::vector<int>& model_index, const TmdFile& f,
                      const std::string& path, const char* kind, double max_value,
                      std::vector<Eigen::Triplet<double>>& out, std::vector<std::string>& warnings) {
  int varying = 0, to_inactive = 0;
  for (Eigen::Index k = 0; k < c.nodes.rows(); ++k) {
    const int a = model_index[static_cast<size_t>(c.nodes(k, 0))], b = model_index[static_cast<size_t>(c.nodes(k, 1))];
    const double g = c.value(0, k);
    if ((a < 0) != (b < 0) && g > 0) ++to_inactive;
    if (!(g >= 0 && g <= max_value))
      throw InputError(path, 0, 0, std::string(kind) + " conductor " + std::to_string(k + 1) + " (" +
                                       nodeName(f, c.nodes(k, 0)) + ", " + nodeName(f, c.nodes(k, 1)) + ") of " +
                                       std::to_string(g) + ", outside 0 … " + std::to_string(max_value));
    if (a < 0 || b < 0 || a == b || g == 0) continue;
    if (varies(c.value.col(k), 0.0)) ++varying;
    out.emplace_back(a, b, g);
    out.emplace_back(b, a, g);
  }
  if (to_inactive)
    warnings.push_back("import: " + std::to_string(to_inactive) + " " + kind +
                       " conductor(s) join an active node to an inactive one (type X): dropped with the X nodes");
  if (varying)
    warnings.push_back("import: " + std::to_string(varying) + " " + kind +
                       " conductor(s) change during the file's run: the first time's values are used throughout");
}

}  // namespace

ThermalSettings thermalFromTmd(const TmdFile& f, const std::string& path, std::vector<std::string>& warnings) {
  ThermalSettings s;
  std::vector<int> model_index(f.node_number.size(), -1);
  for (Eigen::Index i = 0; i < f.nodeCount(); ++i)
    if (f.type[static_cast<size_t>(i)] != "X") {
      model_index[static_cast<size_t>(i)] = s.nodeCount();
      s.node_names.push_back(nodeName(f, i));
    }
  const Eigen::Index n = s.nodeCount();
  if (n == 0) throw InputError(path, 0, 0, "every node is inactive (type X): nothing to solve");
  s.radiative_nodes = 0;  // GR comes from the file; radnet computes no view factor here
  s.capacitance = s.dissipation = Eigen::VectorXd::Zero(n);
  s.fixed_temperature = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::quiet_NaN());
  s.initial_temperature = Eigen::VectorXd::Constant(n, 293.15);
  for (Eigen::Index i = 0; i < f.nodeCount(); ++i)
    if (model_index[static_cast<size_t>(i)] >= 0) importNode(f, path, i, model_index[static_cast<size_t>(i)], s, warnings);
  importConductors(f.gl, model_index, f, path, "GL", kMaxConductance, s.conductors, warnings);
  importConductors(f.gr, model_index, f, path, "GR", kMaxCoupling, s.radiative_couplings, warnings);
  if (f.times_s.size() > 1) {
    for (double t : f.times_s) s.output_times_s.push_back(t - f.times_s.front());
    s.duration_s = s.output_times_s.back();
    s.output_step_s = *s.duration_s / static_cast<double>(f.times_s.size() - 1);
  }
  return s;
}

bool isImportedCase(const YamlDocument& doc) { return doc.root().IsMap() && doc.root()["import"].IsDefined(); }

ImportedCase loadImportedCase(const YamlDocument& doc) {
  const YAML::Node& root = doc.root();
  doc.expectMap(root, "case", {"name", "description", "import", "thermal", "expect"});
  ImportedCase c;
  c.file = doc.file();
  c.yaml_text = doc.text();
  c.name = doc.string(doc.required(root, "name", "case"), "name");
  const YAML::Node import = doc.required(root, "import", "case");
  doc.expectMap(import, "import", {"esatan_tmd"});
  const YAML::Node tmd = doc.required(import, "esatan_tmd", "import");
  std::filesystem::path source = doc.string(tmd, "import.esatan_tmd");
  if (source.is_relative()) source = std::filesystem::path(doc.file()).parent_path() / source;
  c.source = source.string();
  TmdFile f;
  std::vector<std::string> warnings;
  ThermalSettings imported;
  try {
    tryReadInChild(c.source, [&] { readTmd(c.source); });  // a file that crashes HDF5 is refused, not a crash
    f = readTmd(c.source);
    imported = thermalFromTmd(f, c.source, warnings);
  } catch (const InputError& e) {
    throw doc.error(tmd, std::string("import.esatan_tmd: ") + e.what());
  }
  c.time_offset_s = f.times_s.front();
  c.thermal = *parseThermalSettings(doc, imported.node_names, Eigen::VectorXd::Zero(imported.nodeCount()),
                                    std::nullopt, &imported);
  c.thermal.warnings.insert(c.thermal.warnings.begin(), warnings.begin(), warnings.end());
  for (size_t i = 0; i < f.node_number.size(); ++i)
    if (f.type[i] != "X") c.labels.push_back(f.label[i]);
  c.labels.resize(static_cast<size_t>(c.thermal.nodeCount()));
  if (root["expect"]) c.expectations = parseExpectations(doc, root["expect"], {}, c.thermal.node_names);
  return c;
}

}  // namespace radnet::cases
