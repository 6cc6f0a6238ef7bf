#pragma once
// A mesh's `shell:` completed from its file: a NASTRAN PID's PSHELL thickness and MAT4
// conductivity, specific heat and density where the case leaves them out (docs/case-files.md,
// "Shells").
#include "cases/config/geometry_case.hpp"
#include "cases/config/primitive_specs.hpp"

#include <map>
#include <utility>
#include <vector>

namespace radnet::cases {

/// Fills `shell.face_bulk` for the faces the mesh added: `ranges[k]` (scene faces [first, end))
/// came with `bulk[k]`. What the case gives (material, thickness) wins; what it leaves out comes
/// from the file, for every face, or the run stops at `shell_node` naming the group that lacks it.
/// @throws InputError at shell_node
void shellFromFile(const YamlDocument& doc, const YAML::Node& shell_node, const std::map<std::string, Material>& materials,
                   const std::vector<std::pair<int, int>>& ranges, const std::vector<PrimitiveInput::FileBulk>& bulk,
                   ShellSpec& shell);

}  // namespace radnet::cases
