#pragma once
// Patch pairs settled a cluster pair at a time (docs/geometry.md, "Clusters"). Coplanar
// patches facing one way are grouped into compact clusters; for two clusters, their convex
// outlines decide for every pair inside at once: one behind the other's plane (all pairs
// culled), or each wholly in front of the other with no occluder in the shaft between the
// outlines (all pairs see each other whole: no clipping, no per-pair shaft test). Only the
// rest ("mixed") are classified pair by pair.
#include "geometry/exact/patches.hpp"
#include "geometry/exact/shaft.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace radnet::geometry {

enum class ClusterPair : std::uint8_t { Culled, Free, Mixed };

class PatchClusters {
 public:
  /// @param tolerance  m: nearer a plane than this counts as on it (as for pairs)
  /// @param node_pairs when given, whether the caller will look at the pairs of nodes (i, j)
  ///                   at all (ExactOptions::node_pairs): a cluster pair with no such pair of
  ///                   its patches is marked culled unclassified (the turning rows of an
  ///                   articulated part: most cluster pairs lie between fixed parts, and
  ///                   classifying them was 90 % of building the clusters)
  PatchClusters(const std::vector<Patch>& patches, const OccluderIndex& index, double tolerance, int threads,
                const std::function<bool(int, int)>& node_pairs = {});
  int clusterOf(size_t patch) const { return cluster_of_[patch]; }
  size_t size() const { return members_.size(); }
  /// Patches of cluster c, in increasing order.
  const std::vector<int>& members(size_t c) const { return members_[c]; }
  ClusterPair pair(size_t a, size_t b) const { return table_[a * members_.size() + b]; }
  std::int64_t freePairs() const { return free_pairs_; }  ///< patch pairs in free cluster pairs

 private:
  std::vector<int> cluster_of_;
  std::vector<std::vector<int>> members_;
  std::vector<ClusterPair> table_;
  std::int64_t free_pairs_ = 0;
};

}  // namespace radnet::geometry
