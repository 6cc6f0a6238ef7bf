#pragma once
// The geometry form of a case (DESIGN.md §3): materials, surfaces (primitives and mesh
// files, each side naming a material), and how to compute view factors.
#include "cases/network_case.hpp"
#include "cases/orbit_settings.hpp"
#include "cases/thermal_settings.hpp"
#include "cases/yaml_support.hpp"
#include "geometry/contour_view_factors.hpp"
#include "geometry/scene.hpp"
#include "geometry/view_factors.hpp"

#include <map>
#include <string>
#include <vector>

namespace radnet::cases {

struct Material {
  double emissivity = 1.0;    ///< IR, –
  double absorptivity = 1.0;  ///< solar, –
};

enum class ViewFactorMethod { MonteCarlo, Contour };

struct GeometryCase {
  std::string name;
  std::string file;
  std::string yaml_text;
  std::vector<std::pair<std::string, std::string>> included;  ///< (path, text) of included files
  std::map<std::string, Material> materials;
  geometry::Scene scene;                    ///< built while loading (meshes read, validated)
  std::vector<std::string> node_material;   ///< per scene node
  Eigen::VectorXd emissivity, absorptivity;  ///< per scene node
  geometry::ViewFactorOptions view_factors;
  ViewFactorMethod method = ViewFactorMethod::MonteCarlo;
  geometry::ContourOptions contour;
  SolverSettings solver;
  std::optional<OrbitSettings> orbit;  ///< absent: network and exchange factors only
  std::optional<ThermalSettings> thermal;  ///< absent: no temperatures
  std::vector<Expectation> expectations;
};

/// True when the document has a `geometry:` key.
bool isGeometryCase(const YamlDocument& doc);

/// Parses the case and builds its scene. Mesh paths are relative to the case file.
/// @throws InputError with file:line:column (geometry errors located at their surface entry)
GeometryCase loadGeometryCase(const YamlDocument& doc);

}  // namespace radnet::cases
