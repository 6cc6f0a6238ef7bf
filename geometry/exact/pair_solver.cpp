#include "geometry/exact/pair_solver.hpp"

namespace radnet::geometry {

std::vector<int> exactPatches(const ExactScene& scene) {
  std::vector<int> out;
  for (size_t a = 0; a < scene.patches.size(); ++a)
    if (!scene.sampled[a]) out.push_back(static_cast<int>(a));
  return out;
}

size_t pairsFrom(const ExactScene& scene, const ExactOptions& opt, int a) {
  const auto ca = static_cast<size_t>(scene.clusters.clusterOf(static_cast<size_t>(a)));
  size_t count = 0;
  for (size_t c = 0; c < scene.clusters.size(); ++c) {
    if (scene.clusters.pair(ca, c) == ClusterPair::Culled) continue;
    for (int b : scene.clusters.members(c)) count += visitedFrom(scene, a, b) && !filteredOut(scene, opt, a, b);
  }
  return count;
}

}  // namespace radnet::geometry
