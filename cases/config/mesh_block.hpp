#pragma once
// The `mesh` primitive's builder (its row is in primitive_specs.cpp).
#include "cases/config/primitive_specs.hpp"

namespace radnet::cases {

/// Keys: file, scale, rotation {axis, angle}, position, flip, nodes (single, groups,
/// components, faces, elements; `groups: true` is nodes: groups), feature_angle, properties
/// (NASTRAN, by PID), mesh_size (STEP: the tessellation's chord deflection, m).
void buildMesh(const PrimitiveInput& in);

}  // namespace radnet::cases
