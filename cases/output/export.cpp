#include "cases/output/export.hpp"

#include "cases/config/errors.hpp"
#include "cases/config/damaged_file_guard.hpp"
#include "cases/output/deck_text.hpp"
#include "cases/output/hdf5_reader.hpp"
#include "cases/output/output_guard.hpp"
#include "cases/output/tmd_export.hpp"
#include "cases/output/xdmf.hpp"
#include "solver/units.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <sstream>

namespace radnet::cases {
namespace {

using namespace deck;

std::string header(const ExportedNetwork& net, const char* comment) {
  std::ostringstream h;
  h << comment << " radnet export of '" << net.name << "'"
    << (net.design_case.empty() ? "" : ", design case '" + net.design_case + "'") << ", position " << net.position
    << " (t = " << number(net.time_s) << " s)\n"
    << comment << " " << net.nodes.size() << " nodes + space, " << net.gl.size() << " GL, " << net.gr.size()
    << " GR; heat loads and conductances are those of this position\n";
  if (net.transient)
    h << comment << " the temperatures are radnet's transient ones at this position: a steady solve of this deck\n"
      << comment << " gives the steady state under this position's loads, not these temperatures\n";
  if (!net.thermal)
    h << comment << " NO TEMPERATURES: the result has none (its case has no thermal: block); the nodes carry\n"
      << comment << " the absorbed loads of /loads only (no capacitance, no dissipation): give T, C and QI\n";
  if (net.dropped_gr_share > 0)
    h << comment << " GR below the --min-gr threshold left out: at most " << number(100 * net.dropped_gr_share)
      << " % of a node's sum of GR\n";
  return h.str();
}

}  // namespace

void deck::esatanNodesAndConductors(const ExportedNetwork& net, std::ostream& d) {
  const int space = deckNodeNumber(net, static_cast<int>(net.nodes.size()));
  d << "$MODEL RADNET\n$NODES\n";
  for (size_t k = 0; k < net.nodes.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const double c = net.capacitance_j_k[i];
    // Boundary or diffusion; an arithmetic node is a diffusion node of zero capacitance (X is
    // ESATAN's inactive node, which the TMD import drops).
    const char kind = isFixed(net, i) ? 'B' : 'D';
    d << "  " << kind << k + 1 << " = '" << quoted(net.nodes[k], '\'') << "'";
    if (net.thermal) d << ", T = " << celsius(startTemperature(net, i));
    if (kind == 'D' && net.thermal) d << ", C = " << number(c);
    if (!net.lumped[k])
      d << ", A = " << number(net.area_m2[i]) << ", ALP = " << number(net.absorptivity[i])
        << ", EPS = " << number(net.emissivity[i]);
    if (kind != 'B')
      d << ", QS = " << number(net.q_solar_w[i]) << ", QA = " << number(net.q_albedo_w[i])
        << ", QE = " << number(net.q_earth_ir_w[i]) << ", QI = " << number(net.q_internal_w[i]);
    d << ";\n";
  }
  d << "  B" << space << " = 'SPACE', T = " << celsius(net.space_temperature_k) << ";\n$CONDUCTORS\n";
  const auto id = [&](int i) { return deckNodeNumber(net, i); };
  for (const auto& c : net.gl) d << "  GL(" << id(c.i) << ", " << id(c.j) << ") = " << number(c.value) << ";\n";
  for (const auto& c : net.gr) d << "  GR(" << id(c.i) << ", " << id(c.j) << ") = " << number(c.value) << ";\n";
}

std::string esatanDeck(const ExportedNetwork& net) {
  std::ostringstream d;
  d << header(net, "#") << "# Node n is radnet node n−1; temperatures in °C (TABS = 273.15); GR in m²,\n"
    << "# ESATAN applies STEFAN itself; QS, QA, QE: absorbed solar, albedo and Earth IR, W;\n"
    << "# QI: dissipation and heater power at this position, W.\n";
  esatanNodesAndConductors(net, d);
  d << "$CONSTANTS\n$CONTROL\n  TABS = 273.15;\n  STEFAN = " << number(kStefanBoltzmann) << ";\n"
    << "  RELXCA = 1.0E-6;\n  NLOOP = 1000;\n$EXECUTION\n  CALL SOLVFM;\n$OUTPUTS\n"
    << "  CALL PRNDTB(' ', 'L, T, QI', CURRENT);\n$ENDMODEL RADNET\n";
  return d.str();
}

void deck::sindaNodesAndConductors(const ExportedNetwork& net, std::ostream& d) {
  const int space = deckNodeNumber(net, static_cast<int>(net.nodes.size()));
  d << "HEADER NODE DATA, RADNET\n";
  for (size_t k = 0; k < net.nodes.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const double c = net.capacitance_j_k[i];
    if (isFixed(net, i))  // boundary nodes: negative node number
      d << "    -" << k + 1 << ", " << celsius(startTemperature(net, i)) << ", 0.0";
    else
      d << "    " << k + 1 << ", " << celsius(startTemperature(net, i)) << ", " << (c > 0 ? number(c) : "-1.0");
    d << "    $ " << net.nodes[k] << "\n";
  }
  d << "    -" << space << ", " << celsius(net.space_temperature_k) << ", 0.0    $ SPACE\n";
  d << "HEADER CONDUCTOR DATA, RADNET\n";
  const auto id = [&](int i) { return deckNodeNumber(net, i); };
  int conductor = 0;
  for (const auto& c : net.gl)
    d << "    " << ++conductor << ", " << id(c.i) << ", " << id(c.j) << ", " << number(c.value) << "    $ GL W/K\n";
  for (const auto& c : net.gr)
    d << "    -" << ++conductor << ", " << id(c.i) << ", " << id(c.j) << ", " << number(kStefanBoltzmann * c.value)
      << "    $ GR " << number(c.value) << " m^2\n";
}

std::string sindaDeck(const ExportedNetwork& net) {
  std::ostringstream d;
  d << header(net, "C") << "C Node n is radnet node n-1; temperatures in deg C (ABSZRO = -273.15).\n"
    << "C Radiation conductors (negative ids) hold sigma * GR, W/K^4, so SIGMA = 1.0 below.\n"
    << "HEADER OPTIONS DATA\nTITLE radnet export: " << net.name << "\n"
    << "HEADER CONTROL DATA, GLOBAL\n    UID = SI\n    ABSZRO = -273.15\n    SIGMA = 1.0\n"
    << "    NLOOPS = 1000\n    ARLXCA = 1.0E-6\n";
  sindaNodesAndConductors(net, d);
  d << "HEADER SOURCE DATA, RADNET\n";
  for (size_t k = 0; k < net.nodes.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const double q = net.q_solar_w[i] + net.q_albedo_w[i] + net.q_earth_ir_w[i] + net.q_internal_w[i];
    if (q != 0 && !isFixed(net, i)) d << "    " << k + 1 << ", " << number(q) << "    $ W\n";
  }
  d << "HEADER END\n";
  return d.str();
}

std::vector<std::string> csvTables(const ExportedNetwork& net) {
  std::ostringstream nodes, couplings;
  nodes << "index,name,kind,area_m2,emissivity,absorptivity,capacitance_J_K,temperature_K,fixed,"
           "q_solar_W,q_albedo_W,q_earth_ir_W,q_internal_W\n";
  for (size_t k = 0; k < net.nodes.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    nodes << k << ",\"" << quoted(net.nodes[k], '"') << "\"," << (net.lumped[k] ? "lumped" : "surface") << ","
          << number(net.area_m2[i]) << "," << number(net.emissivity[i]) << "," << number(net.absorptivity[i]) << ","
          << number(net.capacitance_j_k[i]) << "," << (net.thermal ? number(startTemperature(net, i)) : "") << ","
          << (isFixed(net, i) ? 1 : 0) << "," << number(net.q_solar_w[i]) << "," << number(net.q_albedo_w[i]) << ","
          << number(net.q_earth_ir_w[i]) << "," << number(net.q_internal_w[i]) << "\n";
  }
  nodes << net.nodes.size() << ",\"space\",space,0,0,0,0," << number(net.space_temperature_k) << ",1,0,0,0,0\n";
  couplings << "kind,node_a,node_b,value,units\n";
  for (const auto& c : net.gl) couplings << "GL," << c.i << "," << c.j << "," << number(c.value) << ",W/K\n";
  for (const auto& c : net.gr) couplings << "GR," << c.i << "," << c.j << "," << number(c.value) << ",m^2\n";
  return {nodes.str(), couplings.str()};
}

namespace {

// The design cases to export: the one named, or every one when none is (each to its own file).
std::vector<std::string> casesToExport(const Hdf5Reader& h5, const ExportOptions& o) {
  if (!o.design_case.empty() || o.position >= 0 || !h5.has("/cases/name")) return {o.design_case};
  const std::vector<std::string> names = h5.strings("/cases/name");
  return names.size() > 1 ? names : std::vector<std::string>{o.design_case};
}

// FILE.ext, or FILE-<case>.ext when several design cases go to several files.
std::string caseFile(const std::string& base, const std::string& design_case, bool several) {
  if (!several) return base;
  const std::filesystem::path path(base);
  return (path.parent_path() / (path.stem().string() + "-" + design_case + path.extension().string())).string();
}

// One deck of a design case: its whole orbit when it has several positions and none was
// chosen, else the position's network.
std::string deckText(const Hdf5Reader& h5, const ExportOptions& o) {
  // The n × n GR are read once: here for a chosen position, by the history for a whole orbit.
  const bool one_position = o.position >= 0;
  ExportedNetwork net = readExportedNetwork(h5, o, one_position);
  if (o.format == "sinda" && !net.thermal)
    throw InputError(h5.path(), 0, 0, "the result has no temperatures (its case has no thermal: block) and a "
                                      "SINDA/FLUINT node needs one: export --format esatan or csv for its loads");
  if (!one_position && net.case_end - net.case_first > 1) {
    const ExportedHistory history = readExportedHistory(h5, o);
    return o.format == "esatan" ? esatanOrbitDeck(history) : sindaOrbitDeck(history);
  }
  if (!one_position) net = readExportedNetwork(h5, o);  // a run of one position: its GR now
  return o.format == "esatan" ? esatanDeck(net) : sindaDeck(net);
}

}  // namespace

std::vector<std::string> exportResult(const std::string& h5_path, const ExportOptions& o) {
  tryReadInChild(h5_path, [&] { readExportedNetwork(Hdf5Reader(h5_path), o); });
  const Hdf5Reader h5(h5_path);
  const std::filesystem::path stem = std::filesystem::path(h5_path).stem();
  if (o.format == "csv") {
    const ExportedNetwork net = readExportedNetwork(h5, o);
    const std::filesystem::path dir = o.output.empty() ? stem.string() + "-export" : o.output;
    const std::vector<std::string> tables = csvTables(net);
    std::error_code ec;
    const bool fresh = !std::filesystem::exists(dir, ec);
    std::filesystem::create_directories(dir);
    try {
      writeTextFilesAtomically({{(dir / "nodes.csv").string(), tables[0]}, {(dir / "conductors.csv").string(), tables[1]}});
    } catch (...) {
      if (fresh) std::filesystem::remove(dir, ec);  // a folder made for a failed export goes too (it is empty)
      throw;
    }
    return {(dir / "nodes.csv").string(), (dir / "conductors.csv").string()};
  }
  if (o.format != "esatan" && o.format != "sinda" && o.format != "tmd")
    throw InputError(h5_path, 0, 0, "--format '" + o.format + "': expected esatan, sinda, csv or tmd");
  const std::string base = !o.output.empty() ? o.output
                           : stem.string() + (o.format == "esatan" ? ".d" : o.format == "sinda" ? ".sin" : ".TMD");
  const std::vector<std::string> cases = casesToExport(h5, o);
  std::vector<std::string> written;
  std::vector<std::pair<std::string, std::string>> decks;
  for (const std::string& design_case : cases) {
    ExportOptions one = o;
    one.design_case = design_case;
    const std::string out = caseFile(base, design_case, cases.size() > 1);
    checkOutputTarget(out, {h5_path}, false);
    if (o.format == "tmd") writeTmdExport(h5, one, out);  // each TMD is published as it is written
    else decks.emplace_back(out, deckText(h5, one));
    written.push_back(out);
  }
  writeTextFilesAtomically(decks);  // every deck or none
  return written;
}

}  // namespace radnet::cases
