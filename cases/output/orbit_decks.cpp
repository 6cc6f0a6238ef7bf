// Whole-orbit decks (docs/export.md, "Whole-orbit decks"): the network at the first
// position, every load that changes over the positions as a doublet array (time, W)
// interpolated linearly in the variables block (cyclically over the orbit), and each
// thermostat as logic on its sensor, so that the other tool integrates radnet's transient.
#include "cases/output/deck_text.hpp"
#include "cases/output/export.hpp"

#include <iomanip>
#include <sstream>

namespace radnet::cases {
namespace {

using namespace deck;

// One load of one node over the positions, W.
struct LoadHistory {
  const char* kind;  ///< QS, QA, QE or QI (W), Q (SINDA's sum, W), or T (a boundary node's, °C)
  int node;
  Eigen::VectorXd value;  ///< per position
};

bool hasThermostatOn(const ExportedHistory& h, int node) {
  return std::any_of(h.thermostats.begin(), h.thermostats.end(), [node](const auto& t) { return t.node == node; });
}

// The internal load the deck interpolates: dissipation alone where the thermostats are logic
// (their power is added by it), dissipation plus heaters otherwise.
double internalLoad(const ExportedHistory& h, const ExportedNetwork& net, Eigen::Index i) {
  return h.thermostats.empty() ? net.q_internal_w[i] : net.q_internal_w[i] - net.q_heater_w[i];
}

// Every (kind, node) whose value changes over the positions; constant ones stay node values.
std::vector<LoadHistory> changingLoads(const ExportedHistory& h, bool summed) {
  std::vector<LoadHistory> out;
  const ExportedNetwork& first = h.at.front();
  const auto P = static_cast<Eigen::Index>(h.at.size());
  for (size_t k = 0; k < first.nodes.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    if (isFixed(first, i)) {  // a boundary node held at a temperature that changes (an imported history), °C
      LoadHistory held{"T", static_cast<int>(k), Eigen::VectorXd(P)};
      for (Eigen::Index p = 0; p < P && first.thermal; ++p) held.value[p] = h.at[static_cast<size_t>(p)].temperature_k[i] - kZeroCelsius;
      if (first.thermal && held.value.maxCoeff() - held.value.minCoeff() > 1e-12 * std::max(1.0, held.value.cwiseAbs().maxCoeff()))
        out.push_back(held);
      continue;
    }
    std::vector<LoadHistory> node = {{"QS", static_cast<int>(k), Eigen::VectorXd(P)}, {"QA", static_cast<int>(k), Eigen::VectorXd(P)},
                                     {"QE", static_cast<int>(k), Eigen::VectorXd(P)}, {"QI", static_cast<int>(k), Eigen::VectorXd(P)}};
    for (Eigen::Index p = 0; p < P; ++p) {
      const ExportedNetwork& net = h.at[static_cast<size_t>(p)];
      node[0].value[p] = net.q_solar_w[i], node[1].value[p] = net.q_albedo_w[i];
      node[2].value[p] = net.q_earth_ir_w[i], node[3].value[p] = internalLoad(h, net, i);
    }
    if (summed) {  // SINDA: one source per node
      node[0].kind = "Q";
      node[0].value += node[1].value + node[2].value + node[3].value;
      node.resize(1);
    }
    // Changing beyond round-off (dissipation + heater − heater is not the dissipation to the last bit).
    for (const LoadHistory& l : node)
      if (l.value.maxCoeff() - l.value.minCoeff() > 1e-12 * std::max(1.0, l.value.cwiseAbs().maxCoeff()) ||
          (summed && hasThermostatOn(h, l.node)))
        out.push_back(l);
  }
  return out;
}

// A time with every digit of its double: the eclipse edges' positions lie seconds apart with
// loads changing by watts per second there, so 12 digits of time would move a load by 1e-8 W.
std::string exactTime(double t) {
  std::ostringstream s;
  s << std::setprecision(17) << t;
  return s.str();
}

// The doublet array of one load: (time, W) per position, closed by the first value one
// period on when the loads repeat.
void doublets(const ExportedHistory& h, const LoadHistory& l, std::ostream& d, const char* indent) {
  for (size_t p = 0; p < h.times_s.size(); ++p)
    d << (p ? ",\n" : "") << indent << exactTime(h.times_s[p]) << ", " << number(l.value[static_cast<Eigen::Index>(p)]);
  if (h.period_s > 0) d << ",\n" << indent << exactTime(h.times_s.front() + h.period_s) << ", " << number(l.value[0]);
}

std::string orbitHeader(const ExportedHistory& h, const char* comment) {
  const ExportedNetwork& first = h.at.front();
  std::ostringstream s;
  s << comment << " radnet whole-orbit export of '" << first.name << "'"
    << (first.design_case.empty() ? "" : ", design case '" + first.design_case + "'") << ": " << h.at.size()
    << " positions, t = " << number(h.times_s.front()) << " ... " << number(h.times_s.back()) << " s\n"
    << comment << " " << first.nodes.size() << " nodes + space, " << first.gl.size() << " GL, " << first.gr.size()
    << " GR; temperatures and conductances at the first position, loads as arrays of (time s, W)\n";
  if (h.period_s > 0)
    s << comment << " loads repeat every " << number(h.period_s) << " s (the orbit sweep): interpolated at\n"
      << comment << " T0 + MOD(time - T0, PERIOD); raise the end time to integrate more orbits\n";
  if (!first.transient && first.thermal)
    s << comment << " radnet's temperatures were steady at each position; this deck integrates a transient\n";
  if (!first.thermal)
    s << comment << " NO TEMPERATURES: the result has none (its case has no thermal: block); loads only\n";
  for (const ExportedThermostat& t : h.thermostats)
    s << comment << " thermostat '" << t.name << "': " << number(t.power_w) << " W on node "
      << deckNodeNumber(first, t.node) << " when node " << deckNodeNumber(first, t.sensor) << " falls below "
      << celsius(t.on_below_k) << " C, off above " << celsius(t.off_above_k) << " C\n";
  const bool heated = std::any_of(h.at.begin(), h.at.end(), [](const auto& n) { return n.q_heater_w.cwiseAbs().sum() > 0; });
  if (h.thermostats.empty() && heated)
    s << comment << " heater power (if any) is in the QI arrays as the run supplied it, not as logic\n";
  return s.str();
}

// The output interval: the positions' median spacing (a sweep is uniform but for eclipse edges).
double outputInterval(const ExportedHistory& h) {
  if (h.times_s.size() < 2) return h.period_s > 0 ? h.period_s : 1.0;
  std::vector<double> dt;
  for (size_t p = 1; p < h.times_s.size(); ++p) dt.push_back(h.times_s[p] - h.times_s[p - 1]);
  std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
  return dt[dt.size() / 2];
}

double endTime(const ExportedHistory& h) { return h.period_s > 0 ? h.times_s.front() + h.period_s : h.times_s.back(); }

}  // namespace

std::string esatanOrbitDeck(const ExportedHistory& h) {
  ExportedNetwork first = h.at.front();
  for (Eigen::Index i = 0; i < first.q_internal_w.size(); ++i) first.q_internal_w[i] = internalLoad(h, first, i);
  const std::vector<LoadHistory> loads = changingLoads(h, false);
  std::ostringstream d;
  d << orbitHeader(h, "#") << "# Node n is radnet node n-1; temperatures in C (TABS = 273.15); GR in m2.\n";
  esatanNodesAndConductors(first, d);
  d << "$CONSTANTS\n$REAL\n  T0 = " << exactTime(h.times_s.front()) << ";\n  PERIOD = " << exactTime(h.period_s)
    << ";\n  TCYC = " << number(h.times_s.front()) << ";\n";
  for (size_t k = 0; k < h.thermostats.size(); ++k) {
    const ExportedThermostat& t = h.thermostats[k];
    d << "  HTP" << k + 1 << " = " << number(t.power_w) << ";\n  HTON" << k + 1 << " = " << celsius(t.on_below_k)
      << ";\n  HTOFF" << k + 1 << " = " << celsius(t.off_above_k) << ";\n";
  }
  if (!h.thermostats.empty()) d << "$INTEGER\n";
  for (size_t k = 0; k < h.thermostats.size(); ++k) d << "  HTR" << k + 1 << " = " << h.thermostats[k].on_at_start << ";\n";
  d << "$CONTROL\n  TABS = 273.15;\n  STEFAN = " << number(kStefanBoltzmann) << ";\n  RELXCA = 1.0E-6;\n  NLOOP = 1000;\n"
    << "  TIMEO = " << number(h.times_s.front()) << ";\n  TIMEND = " << number(endTime(h)) << ";\n  DTIMEI = "
    << number(std::min(10.0, outputInterval(h))) << ";\n  OUTINT = " << number(outputInterval(h)) << ";\n";
  d << "$ARRAYS\n$REAL\n";
  const size_t points = h.times_s.size() + (h.period_s > 0 ? 1 : 0);
  for (const LoadHistory& l : loads) {
    d << "  " << l.kind << "_" << l.node + 1 << "(2, " << points << ") =\n";
    doublets(h, l, d, "    ");
    d << ";\n";
  }
  d << "$VARIABLES1\n";
  d << (h.period_s > 0 ? "  TCYC = T0 + MOD(TIMEM - T0, PERIOD);\n" : "  TCYC = TIMEM;\n");
  for (const LoadHistory& l : loads)
    if (!(std::string(l.kind) == "QI" && hasThermostatOn(h, l.node)))
      d << "  " << l.kind << l.node + 1 << " = INTRP1(TCYC, " << l.kind << "_" << l.node + 1 << ", 1);\n";
  for (size_t k = 0; k < h.thermostats.size(); ++k) {
    const ExportedThermostat& t = h.thermostats[k];
    const int node = t.node + 1, sensor = t.sensor + 1;
    const bool tabled = std::any_of(loads.begin(), loads.end(), [&](const auto& l) { return l.node == t.node && std::string(l.kind) == "QI"; });
    d << "# thermostat '" << t.name << "'\n  IF (T" << sensor << " < HTON" << k + 1 << ") THEN\n    HTR" << k + 1
      << " = 1;\n  ELSE IF (T" << sensor << " > HTOFF" << k + 1 << ") THEN\n    HTR" << k + 1 << " = 0;\n  END IF\n"
      << "  QI" << node << " = "
      << (tabled ? "INTRP1(TCYC, QI_" + std::to_string(node) + ", 1)" : number(first.q_internal_w[t.node]))
      << " + HTR" << k + 1 << " * HTP" << k + 1 << ";\n";
  }
  d << "$EXECUTION\n  CALL SLCRNC;\n$OUTPUTS\n  CALL PRNDTB(' ', 'L, T, QS, QA, QE, QI', CURRENT);\n$ENDMODEL RADNET\n";
  return d.str();
}

std::string sindaOrbitDeck(const ExportedHistory& h) {
  const ExportedNetwork& first = h.at.front();
  const std::vector<LoadHistory> loads = changingLoads(h, true);
  std::ostringstream d;
  d << orbitHeader(h, "C") << "C Node n is radnet node n-1; temperatures in deg C (ABSZRO = -273.15).\n"
    << "C Radiation conductors (negative ids) hold sigma * GR, W/K^4, so SIGMA = 1.0 below.\n"
    << "C Array 1000 + n: node n's total source (solar + albedo + Earth IR + dissipation), (time s, W);\n"
    << "C array 2000 + n: boundary node n's temperature where it changes, (time s, deg C).\n"
    << "HEADER OPTIONS DATA\nTITLE radnet whole-orbit export: " << first.name << "\n"
    << "HEADER CONTROL DATA, GLOBAL\n    UID = SI\n    ABSZRO = -273.15\n    SIGMA = 1.0\n"
    << "    NLOOPS = 1000\n    ARLXCA = 1.0E-6\n    TIMEO = " << number(h.times_s.front()) << "\n    TIMEND = "
    << number(endTime(h)) << "\n    DTIMEI = " << number(std::min(10.0, outputInterval(h))) << "\n    OUTPUT = "
    << number(outputInterval(h)) << "\n";
  d << "HEADER REGISTER DATA\n    T0 = " << exactTime(h.times_s.front()) << "\n    PERIOD = " << exactTime(h.period_s)
    << "\n    TCYC = " << number(h.times_s.front()) << "\n";
  for (size_t k = 0; k < h.thermostats.size(); ++k) {
    const ExportedThermostat& t = h.thermostats[k];
    d << "    HTR" << k + 1 << " = " << (t.on_at_start ? "1.0" : "0.0") << "\n    HTP" << k + 1 << " = "
      << number(t.power_w) << "\n    HTON" << k + 1 << " = " << celsius(t.on_below_k) << "\n    HTOFF" << k + 1
      << " = " << celsius(t.off_above_k) << "\n";
  }
  sindaNodesAndConductors(first, d);
  d << "HEADER SOURCE DATA, RADNET\n";
  for (size_t k = 0; k < first.nodes.size(); ++k) {
    const auto i = static_cast<Eigen::Index>(k);
    const bool tabled = std::any_of(loads.begin(), loads.end(), [&](const auto& l) { return l.node == static_cast<int>(k); });
    const double q = first.q_solar_w[i] + first.q_albedo_w[i] + first.q_earth_ir_w[i] + internalLoad(h, first, i);
    if (!tabled && q != 0 && !isFixed(first, i)) d << "    " << k + 1 << ", " << number(q) << "    $ W, constant\n";
  }
  d << "HEADER ARRAY DATA, RADNET\n";
  const auto array = [](const LoadHistory& l) { return (std::string(l.kind) == "T" ? 2000 : 1000) + l.node + 1; };
  for (const LoadHistory& l : loads) {
    d << "    " << array(l) << " =\n";
    doublets(h, l, d, "        ");
    d << "\n";
  }
  d << "HEADER VARIABLES 1, RADNET\n"
    << (h.period_s > 0 ? "    TCYC = T0 + MOD(TIMEN - T0, PERIOD)\n" : "    TCYC = TIMEN\n");
  for (const LoadHistory& l : loads) d << "    " << l.kind << l.node + 1 << " = D1DEG1(TCYC, A" << array(l) << ")\n";
  for (size_t k = 0; k < h.thermostats.size(); ++k) {
    const ExportedThermostat& t = h.thermostats[k];
    d << "C thermostat '" << t.name << "'\n    IF (T" << t.sensor + 1 << " .LT. HTON" << k + 1 << ") HTR" << k + 1
      << " = 1.0\n    IF (T" << t.sensor + 1 << " .GT. HTOFF" << k + 1 << ") HTR" << k + 1 << " = 0.0\n    Q"
      << t.node + 1 << " = Q" << t.node + 1 << " + HTR" << k + 1 << " * HTP" << k + 1 << "\n";
  }
  d << "HEADER OPERATIONS DATA\n    BUILD ALL\n    CALL FWDBCK\nHEADER END\n";
  return d.str();
}

}  // namespace radnet::cases
