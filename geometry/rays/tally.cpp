#include "geometry/rays/tally.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::geometry::tally {

int classify(const RayCaster& caster, const Hit& hit) {
  if (hit.face < 0) return kSpace;
  const int node = caster.nodeHit(hit);
  return node >= 0 ? node : kBlocked;
}

std::pair<double, double> replicaStats(const std::vector<Tally>& tallies, int target, double per_replica) {
  const double r = static_cast<double>(tallies.size());
  double sum = 0.0, sum2 = 0.0;
  for (const Tally& t : tallies) {
    auto it = t.find(target);
    const double p = it == t.end() ? 0.0 : double(it->second) / per_replica;
    sum += p;
    sum2 += p * p;
  }
  const double mean = sum / r;
  const double var = std::max(0.0, (sum2 - r * mean * mean) / (r - 1.0));
  return {mean, std::sqrt(var / r)};
}

std::set<int> targetsOf(const std::vector<Tally>& tallies) {
  std::set<int> targets;
  for (const Tally& t : tallies)
    for (const auto& kv : t) targets.insert(kv.first);
  return targets;
}

double worstError(const std::vector<Tally>& tallies, double per_replica) {
  double worst = 0.0;
  for (int target : targetsOf(tallies)) worst = std::max(worst, replicaStats(tallies, target, per_replica).second);
  return worst;
}

void rowEstimate(const std::vector<Tally>& tallies, double per_replica, std::vector<std::pair<int, double>>& row,
                 std::vector<std::pair<int, double>>& row_error, double space[2], double blocked[2]) {
  row.clear();
  row_error.clear();
  space[0] = space[1] = blocked[0] = blocked[1] = 0.0;
  for (int target : targetsOf(tallies)) {
    const auto [mean, err] = replicaStats(tallies, target, per_replica);
    if (target == kSpace) {
      space[0] = mean;
      space[1] = err;
    } else if (target == kBlocked) {
      blocked[0] = mean;
      blocked[1] = err;
    } else {
      row.emplace_back(target, mean);
      row_error.emplace_back(target, err);
    }
  }
}

}  // namespace radnet::geometry::tally
