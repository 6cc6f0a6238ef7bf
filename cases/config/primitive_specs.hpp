#pragma once
// One spec per geometry primitive (docs/case-files.md, "Geometry"): its keys, its default
// subdivisions and the builder that turns its parameters into surfaces. The geometry
// block looks a primitive up here; adding a primitive is adding one row to the table
// (docs/design.md, "Where to add things").
#include "cases/config/yaml_document.hpp"
#include "geometry/scene/primitives.hpp"

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace radnet::cases {

/// What a primitive's builder sees: its parameters, and how to add a surface.
struct PrimitiveInput {
  const YamlDocument& doc;
  const YAML::Node& params;  ///< the primitive's mapping
  const std::string& what;   ///< e.g. "geometry[3].rectangle", for messages
  const std::string& name;   ///< the primitive's `name`
  std::pair<int, int> subdivisions;
  int active_sides = 1;          ///< sides that name a material (node grids count nodes per side)
  size_t existing_nodes = 0;     ///< thermal nodes before this primitive (memory check)
  std::filesystem::path folder;  ///< folder of the file that names the primitive (mesh paths)
  /// Adds the triangles `soup` as surface `surface` to node `node` (and `node`.back);
  /// `mesh_file` names the file they came from, for messages.
  std::function<void(const std::string& surface, const std::string& node, const geometry::TriangleSoup& soup,
                     const std::string& mesh_file)>
      add;
  bool front_active = true;  ///< the front side names a material
  /// Records a defect of the input that was repaired or accepted (Scene::noteDefect): one
  /// warning per `kind` for the whole case.
  std::function<void(const std::string& kind, const std::string& where)> note;
  /// As `add`, the sides' materials from a `{front, back}` mapping of the case (a mesh's
  /// `properties:` entry, `sides_what` naming it for messages) instead of the primitive's own.
  std::function<void(const std::string& surface, const std::string& node, const geometry::TriangleSoup& soup,
                     const std::string& mesh_file, const YAML::Node& sides, const std::string& sides_what)>
      add_with_sides;
  /// What the file says of a shell's bulk, one entry per `add`/`add_with_sides` call in
  /// order (a NASTRAN PID's PSHELL T and MAT4 K, CP, RHO; 0 where the file is blank).
  struct FileBulk {
    std::string group;  ///< e.g. "PID 20", for messages
    double thickness_m = 0.0, conductivity = 0.0, density = 0.0, specific_heat = 0.0;
  };
  std::vector<FileBulk>* file_bulk = nullptr;
};

struct PrimitiveSpec {
  std::string_view kind;          ///< the case-file key, e.g. "rectangle"
  std::vector<std::string> keys;  ///< its own keys, besides name, front, back and subdivisions
  std::pair<int, int> default_subdivisions;
  void (*build)(const PrimitiveInput& input);
};

/// Every primitive, in the order the documentation lists them.
const std::vector<PrimitiveSpec>& primitiveSpecs();

/// The spec of `kind`, or nullptr.
const PrimitiveSpec* findPrimitive(std::string_view kind);

/// `subdivisions` or `nodes`: [a, b] or a single count for both (each in [1, 10000]);
/// `fallback` when absent.
std::pair<int, int> parseCounts(const YamlDocument& doc, const YAML::Node& node, const std::string& what,
                                std::pair<int, int> fallback);

/// Refuses `nodes` thermal nodes that could not fit in this machine's memory even as a
/// sparse network (kMinBytesPerNode each: the eigenvectors, the Lanczos basis, the GR
/// factors, the per-position series), before anything is built; the dense n × n matrices
/// are estimated once the scene exists (checkWorkEstimate). @throws InputError at `where`
void checkNodeMemory(const YamlDocument& doc, const YAML::Node& where, const std::string& what, double nodes);

}  // namespace radnet::cases
