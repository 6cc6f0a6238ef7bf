#pragma once
// The geometry form of a case (docs/case-files.md): materials, surfaces (primitives and
// mesh files, each side naming a material), how to compute view factors, and optionally
// an orbit and a thermal model.
#include "cases/config/expectation.hpp"
#include "cases/config/orbit_settings.hpp"
#include "cases/config/solver_block.hpp"
#include "cases/config/thermal_settings.hpp"
#include "cases/config/yaml_document.hpp"
#include "geometry/scene.hpp"
#include "solver/settings.hpp"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace radnet::cases {

struct Material {
  double emissivity = 1.0;    ///< IR, –
  double absorptivity = 1.0;  ///< solar, –
};

/// Included files of a case, (path, text), kept so that a result carries all its input.
using IncludedFiles = std::vector<std::pair<std::string, std::string>>;

struct GeometryCase {
  std::string name;
  std::string file;
  std::string yaml_text;
  IncludedFiles included;
  std::map<std::string, Material> materials;
  geometry::Scene scene;                     ///< built while loading (meshes read, validated)
  std::vector<std::string> node_names;       ///< per scene node, in scene order
  std::vector<std::string> node_material;    ///< per scene node
  Eigen::VectorXd emissivity, absorptivity;  ///< per scene node, –
  ViewFactorSettings view_factors;
  solver::SolverSettings solver;
  std::optional<OrbitSettings> orbit;      ///< absent: network and exchange factors only
  std::optional<ThermalSettings> thermal;  ///< absent: no temperatures
  std::vector<Expectation> expectations;
};

/// True when the document has a `geometry:` key.
bool isGeometryCase(const YamlDocument& doc);

/// Parses the case and builds its scene. Mesh paths are relative to the case file.
/// @throws InputError with file:line:column (geometry errors located at their surface entry)
GeometryCase loadGeometryCase(const YamlDocument& doc);

/// Reads the YAML file named by `node` (relative to the including file) and records it.
/// @throws InputError when missing, unreadable or nested more than 8 deep (a cycle)
YamlDocument includeDocument(const YamlDocument& doc, const YAML::Node& node, const std::string& what, int depth,
                             IncludedFiles& included);

/// Parses `materials:` (with `include:` of material files) into `materials`.
void parseMaterials(const YamlDocument& doc, const YAML::Node& node, std::map<std::string, Material>& materials,
                    IncludedFiles& included, int depth);

}  // namespace radnet::cases
