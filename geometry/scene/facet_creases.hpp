// How facetted a node's curved surface is: the angle between the normals of neighbouring
// facets. A specular surface reflects about the facet's normal where it knows no better, so a
// crease of θ sends reflected rays up to 2θ off the smooth surface's direction (docs/geometry.md,
// "Specular surfaces").
#pragma once

#include "geometry/scene/scene.hpp"

namespace radnet::geometry {

/// The creases between neighbouring facets of one node that do not know their exact normal.
struct FacetCreases {
  double largest_deg = 0.0;  ///< the largest smooth crease (≤ kSharpEdgeDeg), deg
  double mean_deg = 0.0;     ///< the mean over the smooth edges, deg
  int smooth_edges = 0;      ///< edges with a crease in (kFlatDeg, kSharpEdgeDeg]
};

/// Above this angle an edge is taken as a corner the model means (a box's edge), not a
/// facetted curve, deg.
constexpr double kSharpEdgeDeg = 30.0;
/// Below this, neighbouring facets are coplanar for the purpose (rounding of flat meshes), deg.
constexpr double kFlatDeg = 0.05;

/// The creases of node `node`'s facets, edges matched by their vertices' exact positions
/// (meshes are welded before they join the scene). Facets that reflect about a smooth normal
/// (a primitive's exact surface, a file's vertex normals) are left out.
FacetCreases facetCreases(const Scene& scene, int node);

}  // namespace radnet::geometry
