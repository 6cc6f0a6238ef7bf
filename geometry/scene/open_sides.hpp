#pragma once
// Which sides of a scene's triangles have nothing of the scene in front of them: every vertex
// on or behind the side's plane. Such a side sees only sky: a ray leaving it meets nothing
// (the sky kernel casts none from a node of such sides) and any collimated source it faces
// lights it whole (exact sunlight skips its clipping). Wings' outer faces, bus faces nothing
// overhangs: half the triangles of the bench satellites. Found once per geometry:
// RayCaster::openSides() (rays/ray_caster.hpp) holds them for every stage that asks.
#include "geometry/scene/scene.hpp"

#include <cstdint>
#include <vector>

namespace radnet::geometry {

inline constexpr std::uint8_t kFrontOpen = 1;  ///< nothing in front of the side the normal points to
inline constexpr std::uint8_t kBackOpen = 2;   ///< nothing in front of the other side

/// Per face, kFrontOpen | kBackOpen as they hold. The test reads the vertices of the scene's
/// convex hull (a plane has every vertex behind it exactly when it has these behind it), so
/// it costs faces × hull vertices; a vertex within 1e-9 of the scene's size of a plane lies
/// on it (coplanar neighbours' round-off).
std::vector<std::uint8_t> openSides(const Scene& scene);

/// Whether every triangle of `node` is open on the node's side.
bool nodeOpen(const Node& node, const std::vector<std::uint8_t>& open_sides);

}  // namespace radnet::geometry
