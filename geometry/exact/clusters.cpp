#include "geometry/exact/clusters.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

// Patches of one plane and side, split at the median of the longest axis of their
// centroids' box until a cluster holds at most `size` of them.
void splitCluster(std::vector<int> ids, const std::vector<Vec3>& centre, size_t size,
                  std::vector<std::vector<int>>& out) {
  if (ids.size() <= size) {
    std::sort(ids.begin(), ids.end());
    out.push_back(std::move(ids));
    return;
  }
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (int i : ids) lo = lo.cwiseMin(centre[size_t(i)]), hi = hi.cwiseMax(centre[size_t(i)]);
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const auto mid = ids.begin() + static_cast<std::ptrdiff_t>(ids.size() / 2);
  std::nth_element(ids.begin(), mid, ids.end(),
                   [&](int a, int b) { return centre[size_t(a)][axis] < centre[size_t(b)][axis]; });
  splitCluster(std::vector<int>(ids.begin(), mid), centre, size, out);
  splitCluster(std::vector<int>(mid, ids.end()), centre, size, out);
}

// Convex outline (counter-clockwise about n) of the patches' vertices (monotone chain).
Loop outline(const std::vector<Patch>& patches, const std::vector<int>& ids, const Vec3& n) {
  const Vec3 e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  std::vector<std::pair<std::array<double, 2>, Vec3>> pts;
  for (int i : ids)
    for (const Loop& l : patches[size_t(i)].pieces)
      for (const Vec3& v : l) pts.push_back({{e1.dot(v), e2.dot(v)}, v});
  std::sort(pts.begin(), pts.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  auto cross = [](const auto& o, const auto& a, const auto& b) {
    return (a.first[0] - o.first[0]) * (b.first[1] - o.first[1]) - (a.first[1] - o.first[1]) * (b.first[0] - o.first[0]);
  };
  std::vector<std::pair<std::array<double, 2>, Vec3>> hull(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  Loop out;
  for (size_t i = 0; i + 1 < k; ++i) out.push_back(hull[i].second);  // e1 × e2 = n: counter-clockwise
  return out;
}

struct Outline {
  Patch plane;  // region.normal, offset and pieces = {convex outline}
  std::vector<Vec3> points;
};

ClusterPair classify(const OccluderIndex& index, const Outline& a, const Outline& b, double tol,
                     std::vector<int>& candidates, std::vector<int>& blockers) {
  if (allBehind(b.points, a.plane, tol) || allBehind(a.points, b.plane, tol)) return ClusterPair::Culled;
  if (anyBehind(b.points, a.plane, tol) || anyBehind(a.points, b.plane, tol)) return ClusterPair::Mixed;
  pairBlockers(index, a.plane, a.plane.pieces, b.plane, b.plane.pieces, tol, candidates, blockers);
  return blockers.empty() ? ClusterPair::Free : ClusterPair::Mixed;
}

// Whether the caller keeps any pair of a patch of one cluster with a patch of the other (an
// inactive side, node −1, is always kept: as the exact method's filter).
bool anyKept(const std::vector<Patch>& patches, const std::vector<int>& a, const std::vector<int>& b,
             const std::function<bool(int, int)>& node_pairs) {
  for (int p : a)
    for (int q : b) {
      const int i = patches[size_t(p)].node, j = patches[size_t(q)].node;
      if (i < 0 || j < 0 || node_pairs(i, j)) return true;
    }
  return false;
}

}  // namespace

PatchClusters::PatchClusters(const std::vector<Patch>& patches, const OccluderIndex& index, double tol,
                             int threads, const std::function<bool(int, int)>& node_pairs) {
  // Clusters of about √n / 4 patches (at least 16): the table of cluster pairs stays near
  // n / 16 entries while most pairs of a flat, finely meshed face share one.
  const size_t size = std::max<size_t>(16, static_cast<size_t>(std::sqrt(double(patches.size())) / 4));
  std::map<std::array<long long, 4>, std::vector<int>> planes;
  std::vector<Vec3> centre;
  double extent = 1e-300;
  for (const Patch& p : patches) extent = std::max(extent, (p.hi - p.lo).norm());
  for (const Patch& p : patches) extent = std::max(extent, p.hi.cwiseAbs().maxCoeff());
  for (size_t i = 0; i < patches.size(); ++i) {
    const Patch& p = patches[i];
    const Vec3& n = p.region.normal;
    constexpr double kSteps = 1e9;
    planes[{std::llround(n.x() * kSteps), std::llround(n.y() * kSteps), std::llround(n.z() * kSteps),
            std::llround(p.offset / extent * kSteps)}]
        .push_back(static_cast<int>(i));
    centre.push_back(0.5 * (p.lo + p.hi));
  }
  for (auto& [key, ids] : planes) splitCluster(std::move(ids), centre, size, members_);
  cluster_of_.assign(patches.size(), -1);
  std::vector<Outline> outlines(members_.size());
  for (size_t c = 0; c < members_.size(); ++c) {
    const Patch& first = patches[size_t(members_[c][0])];
    for (int i : members_[c]) cluster_of_[size_t(i)] = static_cast<int>(c);
    Outline& o = outlines[c];
    o.plane.region.normal = first.region.normal;
    o.plane.offset = first.offset;
    o.points = outline(patches, members_[c], first.region.normal);
    o.plane.pieces = {o.points};
  }
  const size_t count = members_.size();
  table_.assign(count * count, ClusterPair::Culled);
  std::int64_t free_pairs = 0;
#ifdef _OPENMP
#pragma omp parallel num_threads(threads) reduction(+ : free_pairs)
#endif
  {
    std::vector<int> candidates, blockers;
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 4)
#endif
    for (size_t a = 0; a < count; ++a)
      for (size_t b = a + 1; b < count; ++b) {
        const ClusterPair kind = node_pairs && !anyKept(patches, members_[a], members_[b], node_pairs)
                                     ? ClusterPair::Culled
                                 : outlines[a].points.size() < 3 || outlines[b].points.size() < 3
                                     ? ClusterPair::Mixed
                                     : classify(index, outlines[a], outlines[b], tol, candidates, blockers);
        table_[a * count + b] = table_[b * count + a] = kind;
        if (kind == ClusterPair::Free)
          free_pairs += static_cast<std::int64_t>(members_[a].size() * members_[b].size());
      }
  }
  free_pairs_ = free_pairs;
  (void)threads;
}

}  // namespace radnet::geometry
