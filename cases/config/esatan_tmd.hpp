#pragma once
// ESATAN-TMS's TMD results file (HDF5), as ESATAN writes it and its readers expect
// (docs/export.md, "TMD"): /AnalysisSet1 holds the nodes, the names of their 16 real
// attributes and the conductor pairs; /AnalysisSet1/DataGroup1 holds, at every output time,
// each node's 16 values (temperature in °C), type and label, and each conductor's value.
#include <Eigen/Dense>

#include <array>
#include <string>
#include <vector>

namespace radnet::cases {

/// The 16 real attributes of a node, in the order ESATAN writes them.
inline constexpr std::array<const char*, 16> kTmdRealAttributes = {
    "Temperature",          "Capacitance",           "Total_Albedo_Heat_Source",    "Total_Earth_Heat_Source",
    "Total_Internal_Heat_Source", "Total_Rest_Heat_Source", "Total_Solar_Heat_Source", "Area",
    "Solar_Absorptivity",   "Infra-Red_Emissivity",  "Incident_Albedo_Heat_Source", "Incident_Earth_Heat_Source",
    "Incident_Solar_Heat_Source", "X_Coordinate",    "Y_Coordinate",                "Z_Coordinate"};

/// Column of each real attribute in TmdFile::real (kTmdRealAttributes order).
enum TmdColumn : int {
  kTmdTemperature = 0, kTmdCapacitance = 1, kTmdAlbedo = 2, kTmdEarth = 3, kTmdInternal = 4, kTmdRest = 5,
  kTmdSolar = 6, kTmdArea = 7, kTmdAbsorptivity = 8, kTmdEmissivity = 9, kTmdIncidentAlbedo = 10,
  kTmdIncidentEarth = 11, kTmdIncidentSolar = 12, kTmdX = 13, kTmdY = 14, kTmdZ = 15
};

struct TmdConductors {
  Eigen::MatrixXi nodes;  ///< (M×2) 0-based rows of the node table
  Eigen::MatrixXd value;  ///< (nt×M) at each output time: GL in W/K, GR in m²
};

struct TmdFile {
  std::string description;
  double celsius_offset_k = 273.15;      ///< TAbs: T(K) = T(°C) + TAbs
  double stefan_boltzmann = 5.670374419e-8;  ///< W/(m² K⁴), as the file states it
  std::vector<int> node_number;          ///< N, ESATAN's node numbers
  std::vector<std::string> type, label;  ///< N: "D" diffusion, "B" boundary, "X" inactive; the label
  std::vector<double> times_s;           ///< nt output times, s
  std::vector<Eigen::MatrixXd> real;     ///< nt × (N×16) in kTmdRealAttributes order (temperature °C)
  TmdConductors gl, gr;
  Eigen::Index nodeCount() const { return static_cast<Eigen::Index>(node_number.size()); }
};

/// Reads a TMD. Every count is bounded by what the file could hold before anything is
/// allocated. @throws InputError naming the file and the missing or malformed path
TmdFile readTmd(const std::string& path);

}  // namespace radnet::cases
