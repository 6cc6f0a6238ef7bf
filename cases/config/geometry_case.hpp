#pragma once
// The geometry form of a case (docs/case-files.md): materials, surfaces (primitives and
// mesh files, each side naming a material), how to compute view factors, and optionally
// an orbit and a thermal model.
#include "cases/config/articulation.hpp"
#include "cases/config/design_cases.hpp"
#include "cases/config/expectation.hpp"
#include "cases/config/orbit_settings.hpp"
#include "cases/config/output_settings.hpp"
#include "cases/config/solver_block.hpp"
#include "cases/config/thermal_settings.hpp"
#include "cases/config/yaml_document.hpp"
#include "geometry/rays/specular.hpp"
#include "geometry/scene/scene.hpp"
#include "geometry/scene/seams.hpp"
#include "solver/radiative/settings.hpp"
#include "solver/thermal/optics.hpp"

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace radnet::cases {

/// A material: optical properties for surfaces that name it, bulk properties for shells.
/// Either set may be absent (a bulk-only material cannot be a surface's side).
/// The temperature at which a tabulated ε or α gives the material's nominal value (what the
/// view factors' report, the loads and the first GR use before the temperatures are known), K.
inline constexpr double kNominalOpticsTemperature = 293.15;

struct Material {
  bool has_optics = false;
  double emissivity = 1.0;    ///< IR, – (with a curve: its value at kNominalOpticsTemperature)
  double absorptivity = 1.0;  ///< solar, – (likewise)
  /// ε(T) and α(T) when given as tables (docs/case-files.md, "Optics against temperature");
  /// an empty warming table: the constant above.
  solver::OpticalCurve emissivity_curve, absorptivity_curve;
  bool hasCurves() const {
    return !emissivity_curve.warming.temperature_k.empty() || !absorptivity_curve.warming.temperature_k.empty();
  }
  /// Specular reflectance ρs and transmittance τ per band (docs/case-files.md, "Specular and
  /// transmissive surfaces"): IR (with ε) and solar (with α); the diffuse reflectance is what
  /// remains, ρd = 1 − ε − ρs − τ. Zero: a diffuse, opaque surface.
  double specular_ir = 0.0, transmittance_ir = 0.0;
  double specular_solar = 0.0, transmittance_solar = 0.0;
  /// The solar values were given (not defaulted to the IR ones): an optical set that changes
  /// the IR value leaves them, where a defaulted one follows it.
  bool solar_specular_given = false, solar_transmittance_given = false;
  bool isSpecular() const {
    return specular_ir > 0 || transmittance_ir > 0 || specular_solar > 0 || transmittance_solar > 0;
  }
  bool has_bulk = false;
  double conductivity = 0.0;   ///< W/(m K)
  double density = 0.0;        ///< kg/m³
  double specific_heat = 0.0;  ///< J/(kg K)
};

/// A primitive's `shell: {material, thickness}`: the thin plate its surfaces are, giving
/// capacitance and conductors to its nodes (docs/case-files.md, "Shells").
struct ShellSpec {
  int first_face = 0, end_face = 0;  ///< the primitive's scene faces
  std::string material;      ///< empty: every face's bulk from the file (face_bulk)
  double thickness_m = 0.0;  ///< 0: every face's thickness from the file (face_bulk)
  /// Per face of [first_face, end_face), where a NASTRAN file gives them (PSHELL T, MAT4 K,
  /// CP, RHO); empty: the material and thickness above for every face.
  struct FaceBulk {
    double thickness_m = 0.0, conductivity = 0.0, rho_c = 0.0;  ///< m, W/(m K), J/(m³ K)
  };
  std::vector<FaceBulk> face_bulk;
  std::string what;  ///< e.g. "geometry[2].rectangle.shell", for messages
  std::string file;  ///< where the case gives it, for messages
  int line = 0, column = 0;
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
  geometry::SeamReport seams;                ///< seams closed between curved primitives
  std::vector<std::string> node_names;       ///< per scene node, in scene order
  std::vector<std::string> node_material;    ///< per scene node
  /// Per scene node, –: the materials' ε and α, or, when a surface is specular or transmissive,
  /// the network's ε/κ and α/κ (κ = 1 − ρs − τ of the band; docs/solver.md, "Specular and
  /// transmissive surfaces"); the optical sets likewise. `surface_*` keep the materials' own.
  Eigen::VectorXd emissivity, absorptivity;
  Eigen::VectorXd surface_emissivity, surface_absorptivity;  ///< as the materials give them, –
  /// ρs and τ per scene node in the IR and the solar band; empty when no surface is specular
  /// or transmissive.
  geometry::SpecularBand specular_ir, specular_solar;
  bool hasSpecular() const { return !specular_ir.empty(); }
  /// The solar band needs its own traced network (its ρs or τ differ from the IR band's somewhere).
  bool solarSpecularDiffers() const {
    return hasSpecular() && !specular_ir.sameAs(specular_solar);
  }
  ViewFactorSettings view_factors;
  solver::SolverSettings solver;
  std::vector<OpticalSet> optical_sets;    ///< `base` (the materials as given) first, then `optics:`
  std::vector<DesignCase> design_cases;    ///< at least one (`base` without `cases:`); their orbits
  std::optional<OpticalUncertainty> optical_uncertainty;
  /// `limits: {node: [min_K, max_K]}`: allowed temperatures (radnet report checks the envelope)
  struct TemperatureLimit {
    int node;
    double min_k, max_k;
  };
  std::vector<TemperatureLimit> limits;
  std::optional<ThermalSettings> thermal;  ///< absent: no temperatures
  std::vector<ShellSpec> shells;
  OutputSettings output;  ///< `output:` which matrices are also written densely
  Articulation articulation;  ///< `articulation:` parts that turn (docs/case-files.md, "Moving parts")
  std::vector<Expectation> expectations;
  std::vector<std::string> warnings;  ///< accepted but suspicious input, printed when the run starts
  /// True when the cases have orbits (all of them or none): network and exchange factors only without.
  bool hasOrbit() const { return !design_cases.empty() && design_cases.front().orbit.has_value(); }
  /// True when a stage after the network reads σ_F (the sweeps' and temperatures' view-factor
  /// uncertainty, the optical samples'): otherwise a σ_F written out early is not held.
  bool readsViewFactorErrors() const { return hasOrbit() || thermal.has_value() || optical_uncertainty.has_value(); }
  /// The materials with optical properties, sorted: the axis of the sensitivities (a
  /// material no surface is made of has a zero row).
  std::vector<std::string> opticalMaterials() const;
};

/// Adds each shell's capacitance and conductors to the thermal model.
/// @throws InputError at the shell when the case has no thermal block
void applyShells(GeometryCase& c);

/// True when the document has a `geometry:` key.
bool isGeometryCase(const YamlDocument& doc);

/// Parses the case and builds its scene. Mesh paths are relative to the case file.
/// @throws InputError with file:line:column (geometry errors located at their surface entry)
GeometryCase loadGeometryCase(const YamlDocument& doc);

/// Reads the YAML file named by `node` (relative to the including file) and records it.
/// @throws InputError when missing, unreadable or nested more than 8 deep (a cycle)
YamlDocument includeDocument(const YamlDocument& doc, const YAML::Node& node, const std::string& what, int depth,
                             IncludedFiles& included);

/// Fills the nodes' specular optics from their materials and, when any surface reflects
/// specularly or transmits, turns ε, α and every optical set into the network's ε/κ, α/κ.
/// @throws InputError at `optics:` when a set's ε (α) + ρs + τ exceeds 1
void applySpecularOptics(const YamlDocument& doc, GeometryCase& c);

/// Warnings, by node, for specular meshes whose facets (without exact or file normals) meet at
/// creases that could put more than solver.accuracy into what they reflect, and for
/// transmissive nodes whose triangles have an inactive other side (a one-way window).
void warnSpecularSurfaces(GeometryCase& c);

/// Parses `materials:` (with `include:` of material files) into `materials`.
void parseMaterials(const YamlDocument& doc, const YAML::Node& node, std::map<std::string, Material>& materials,
                    IncludedFiles& included, int depth);

}  // namespace radnet::cases
