#pragma once
// radnet export: a result's thermal network for another tool (docs/export.md): nodes with
// capacitance, temperature and heat loads at one position, GL and GR couplings, and the
// space node. Formats: ESATAN-TMS (TMD deck), SINDA/FLUINT (input deck), CSV.
#include <Eigen/Dense>

#include <string>
#include <vector>

namespace radnet::cases {

class Hdf5Reader;

/// The network as read back from a result, at one position of one design case.
struct ExportedNetwork {
  std::string name;
  std::string design_case;   ///< "" without design cases
  int position = 0;          ///< global position index (row of /solution/temperature)
  int case_first = 0, case_end = 1;  ///< the design case's positions: case_first … case_end − 1
  double time_s = 0.0;       ///< of that position within its orbit case
  std::vector<std::string> nodes;
  std::vector<bool> lumped;
  Eigen::VectorXd area_m2, emissivity, absorptivity;  ///< (n)
  Eigen::VectorXd capacitance_j_k;                    ///< (n); 0: arithmetic node
  Eigen::VectorXd temperature_k;                      ///< (n), radnet's at the position (NaN without thermal)
  Eigen::VectorXd fixed_temperature_k;                ///< (n), NaN for free nodes
  Eigen::VectorXd q_solar_w, q_albedo_w, q_earth_ir_w, q_internal_w;  ///< (n) at the position; internal: dissipation + heaters
  Eigen::VectorXd q_heater_w;                                         ///< (n) the heaters' part of q_internal_w
  struct Coupling {
    int i, j;  ///< node indices, i < j; j == n: the space node
    double value;
  };
  std::vector<Coupling> gl;  ///< W/K
  std::vector<Coupling> gr;  ///< m²
  double space_temperature_k = 3.0;
  double dropped_gr_share = 0.0;  ///< the largest share of a node's Σ GR left out by min_gr
  bool thermal = false;
  bool transient = false;  ///< radnet's temperatures come from a transient (a steady solve of the deck differs)
};

/// A thermostat heater of the run with its set points (results written before they were
/// stored have none: their heater power then goes with the dissipation).
struct ExportedThermostat {
  std::string name;
  int node = 0, sensor = 0;  ///< node indices
  double power_w = 0.0, on_below_k = 0.0, off_above_k = 0.0;
  bool on_at_start = false;  ///< on at the first position
};

/// Every position of one design case: what a whole-orbit deck and a TMD hold.
struct ExportedHistory {
  std::vector<ExportedNetwork> at;  ///< per position, in order; GR in the first only (the case's optical set)
  std::vector<double> times_s;      ///< their times, increasing, s
  double period_s = 0.0;            ///< the loads repeat with it (the orbit sweep's span), s; 0: they do not
  std::vector<ExportedThermostat> thermostats;
};

struct ExportOptions {
  std::string format = "esatan";  ///< esatan | sinda | csv
  std::string output;             ///< file (esatan, sinda) or directory (csv)
  std::string design_case;        ///< by name; "" the first
  int position = -1;              ///< global index; −1: every position of the design case (decks: a
                                  ///< whole-orbit deck when it has several), the first where one is needed
  double min_gr = 0.0;            ///< GR_ij below min_gr × Σ_k GR_ik of both nodes are left out
};

/// Reads the network to export. @throws InputError on an unknown case, a position outside it, or min_gr ∉ [0, 1)
/// @param couplings  false: GR left out (a history reads them once: they do not change over a case)
ExportedNetwork readExportedNetwork(const Hdf5Reader& h5, const ExportOptions& options, bool couplings = true);

/// Node numbers in every deck and TMD: radnet node i is i + 1; the space node (index n) is
/// 99999, or n + 1 on a model that large.
int deckNodeNumber(const ExportedNetwork& net, int i);

/// Every position of the design case. @throws InputError when its positions belong to several
/// orbit cases (their times do not increase) or the result is malformed
ExportedHistory readExportedHistory(const Hdf5Reader& h5, const ExportOptions& options);

std::string esatanDeck(const ExportedNetwork& net);
std::string sindaDeck(const ExportedNetwork& net);
/// Whole-orbit decks: each load that changes over the positions as an array of time against
/// power, interpolated (cyclically with an orbit) in the decks' variables blocks, and each
/// thermostat as logic on its sensor; a transient run over the case's span.
std::string esatanOrbitDeck(const ExportedHistory& history);
std::string sindaOrbitDeck(const ExportedHistory& history);
/// nodes.csv and conductors.csv, in that order.
std::vector<std::string> csvTables(const ExportedNetwork& net);

/// The whole command: read, format, write (atomically). @return the files written
std::vector<std::string> exportResult(const std::string& h5_path, const ExportOptions& options);

}  // namespace radnet::cases
