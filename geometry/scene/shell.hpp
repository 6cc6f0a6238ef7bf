#pragma once
// How the thermal nodes of a thin shell touch each other, for conduction along and through
// it (docs/geometry.md, "Shells"). Geometry only: the caller turns lengths and areas into
// conductances with the shell's material.
#include "geometry/scene/scene.hpp"

#include <vector>

namespace radnet::geometry {

struct ShellAdjacency {
  /// Two nodes of the same side whose triangles share edges.
  struct Neighbours {
    int a = -1, b = -1;
    double shared_length_m = 0.0;  ///< L: total length of the shared edges
    double distance_m = 0.0;       ///< d: centroid of a → midpoint of the shared edges → centroid of b
    double distance_a_m = 0.0;     ///< the part of d from a's centroid to the midpoint
    double distance_b_m = 0.0;     ///< the part of d from the midpoint to b's centroid
  };
  /// The front and back node of two-sided triangles, and the area they share.
  struct FrontBack {
    int front = -1, back = -1;
    double area_m2 = 0.0;
  };
  std::vector<Neighbours> neighbours;
  std::vector<FrontBack> front_back;
};

/// Adjacency of the nodes on scene faces [first_face, end_face). Triangles touch where
/// their edges coincide (vertices closer than 1e-9 of the faces' extent are one), as the
/// cells of a node grid, the faces of a box and a mesh's triangles do; d is the path from
/// one centroid through the midpoint of the shared edges to the other, which is the
/// centroid distance for neighbours in a plane and follows the fold across an edge.
ShellAdjacency shellAdjacency(const Scene& scene, int first_face, int end_face);

}  // namespace radnet::geometry
