#pragma once
// Which occluders can block a pair of patches (shaft culling, after Haines & Wallace 1994):
// a bounding-volume hierarchy over the occluders' boxes gives those in the box of the
// pair; of these, an occluder can block a segment from P to Q only if it reaches in
// front of both planes, its plane separates P from Q, and it is inside every plane of the
// convex hull of P ∪ Q that an edge of one patch and a vertex of the other span.
#include "geometry/exact/patches.hpp"

#include <vector>

namespace radnet::geometry {

class OccluderIndex {
 public:
  explicit OccluderIndex(std::vector<Occluder> occluders);
  const std::vector<Occluder>& occluders() const { return occluders_; }
  /// Indices of the occluders whose boxes overlap [lo, hi], appended to `out`.
  void query(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const;

 private:
  struct BoxNode {
    Vec3 lo, hi;
    int first = 0, count = 0;  ///< leaf: occluders order_[first, first + count)
    int left = -1, right = -1;
  };
  int build(int first, int count);
  std::vector<Occluder> occluders_;
  std::vector<int> order_;
  std::vector<BoxNode> nodes_;
};

/// The occluders that may block segments between the points of p and of q (p and q
/// already clipped in front of each other's planes). `tolerance` (m) is the distance
/// below which a point counts as on a plane: touching is not blocking.
void pairBlockers(const OccluderIndex& index, const Patch& p, const std::vector<Loop>& p_pieces, const Patch& q,
                  const std::vector<Loop>& q_pieces, double tolerance, std::vector<int>& candidates,
                  std::vector<int>& blockers);

/// Whether one convex occluder hides all of q from all of p: every segment between a
/// vertex of p and a vertex of q passes through its interior. (For fixed q the points of
/// P's plane whose segment to q crosses the occluder form a convex cone section, so the
/// vertices decide; then the same holds for q.) Touching is not hiding.
bool fullyOccludes(const Occluder& o, const std::vector<Loop>& p_pieces, const std::vector<Loop>& q_pieces,
                   double tolerance);

}  // namespace radnet::geometry
