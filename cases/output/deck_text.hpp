#pragma once
// What the ESATAN and SINDA/FLUINT decks of one position and of a whole orbit share
// (cases/output/export.cpp, orbit_decks.cpp): number formatting, node temperatures, and the
// node and conductor blocks.
#include "cases/output/export.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <string>

namespace radnet::cases::deck {

inline constexpr double kStefanBoltzmann = 5.670374419e-8;  // W/(m² K⁴), CODATA 2018 (exact in SI)
inline constexpr double kZeroCelsius = 273.15;               // K

/// 12 significant digits: a deck re-solved reproduces radnet's temperatures to ~1e-9 K.
inline std::string number(double v) {
  std::ostringstream s;
  s << std::setprecision(12) << v;
  return s.str();
}

inline std::string celsius(double k) { return number(k - kZeroCelsius); }

/// A node name inside a quoted label or field: the quote it would end is replaced.
inline std::string quoted(const std::string& name, char quote) {
  std::string s = name;
  std::replace(s.begin(), s.end(), quote, '_');
  return s;
}

inline bool isFixed(const ExportedNetwork& net, Eigen::Index i) { return std::isfinite(net.fixed_temperature_k[i]); }

/// The temperature a node starts from (or is held at): radnet's; NaN for a result without
/// temperatures (never a made-up 20 °C: the decks then say that none exist).
inline double startTemperature(const ExportedNetwork& net, Eigen::Index i) {
  if (isFixed(net, i)) return net.fixed_temperature_k[i];
  return net.thermal ? net.temperature_k[i] : NAN;
}

/// ESATAN `$MODEL RADNET`, `$NODES` (at net's position) and `$CONDUCTORS`.
void esatanNodesAndConductors(const ExportedNetwork& net, std::ostream& d);
/// SINDA/FLUINT node and conductor data (at net's position).
void sindaNodesAndConductors(const ExportedNetwork& net, std::ostream& d);

}  // namespace radnet::cases::deck
