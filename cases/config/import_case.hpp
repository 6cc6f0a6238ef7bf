#pragma once
// The imported case form (docs/export.md, "TMD in"): a thermal network read from another
// tool's results file, solved by radnet at that file's output times.
//   name: disc
//   import: {esatan_tmd: DISCTR_TRANSIENT.TMD}
//   thermal: {...}   # optional: adds to or overrides the imported model
#include "cases/config/esatan_tmd.hpp"
#include "cases/config/expectation.hpp"
#include "cases/config/thermal_settings.hpp"
#include "cases/config/yaml_document.hpp"

#include <string>
#include <vector>

namespace radnet::cases {

struct ImportedCase {
  std::string name;
  std::string file;       ///< the case file
  std::string yaml_text;  ///< its text
  std::string source;     ///< the imported file, as found (relative paths from the case's folder)
  std::vector<std::string> labels;  ///< per thermal node: its label in the file ("" for nodes the case adds)
  double time_offset_s = 0.0;       ///< the file's first output time: radnet's times count from it
  ThermalSettings thermal;          ///< the imported model with the case's `thermal:` on top
  std::vector<Expectation> expectations;
};

/// True when the document is of the imported form (has an `import:` key).
bool isImportedCase(const YamlDocument& doc);

/// Reads the case and the file it imports. @throws InputError (the case's position, then the
/// imported file's name and what in it is missing or malformed)
ImportedCase loadImportedCase(const YamlDocument& doc);

/// The thermal model of a TMD: D nodes (diffusion; capacitance 0: arithmetic) and B nodes
/// (boundary, held at their temperature, following it where it changes) named by type letter and number ("D1000"), X nodes
/// and every conductor touching one dropped; capacitances, GL and GR at the first time
/// (duplicates summed); each node's heat sources (solar, albedo, Earth, internal, rest)
/// summed and interpolated linearly between the output times; the transient run from the
/// first time's temperatures and output at the file's times (one time: a steady state).
/// @param warnings  what was read but is not exactly what the file's run used
/// @throws InputError naming the file and the node
ThermalSettings thermalFromTmd(const TmdFile& f, const std::string& path, std::vector<std::string>& warnings);

}  // namespace radnet::cases
