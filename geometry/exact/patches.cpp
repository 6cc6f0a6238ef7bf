#include "geometry/exact/patches.hpp"

#include "geometry/scene/vertex_welder.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <unordered_map>

namespace radnet::geometry {
namespace {

// Triangles grouped by a tag (node side) and their plane. Planes are keyed on the normal
// and offset rounded to 1e-9 (offset relative to the scene's extent): two triangles one
// rounding step apart merely land in different groups, which costs time, never accuracy.
struct PlaneKey {
  long tag;
  std::array<long long, 4> q;
  bool operator<(const PlaneKey& o) const { return tag != o.tag ? tag < o.tag : q < o.q; }
};

struct Group {
  Vec3 normal;
  std::vector<std::array<Vec3, 3>> triangles;  // counter-clockwise about `normal`
};

PlaneKey planeKey(long tag, const Vec3& n, double offset, double extent) {
  constexpr double kSteps = 1e9;
  return {tag,
          {std::llround(n.x() * kSteps), std::llround(n.y() * kSteps), std::llround(n.z() * kSteps),
           std::llround(offset / extent * kSteps)}};
}

// Boundary loops of a set of triangles: directed edges that no neighbour runs backwards,
// chained. Empty when they do not chain into simple loops (T-junctions, bow-ties).
std::vector<Loop> boundaryLoops(const std::vector<std::array<Vec3, 3>>& triangles, double weld_tolerance) {
  // Cells meshed one by one meet at corners computed in different ways: weld them.
  VertexWelder welder(weld_tolerance);
  auto id = [&](const Vec3& p) { return welder.id(p); };
  std::map<std::pair<int, int>, int> edges;  // directed edge → net count
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = id(t[static_cast<size_t>(k)]), b = id(t[static_cast<size_t>((k + 1) % 3)]);
      const auto back = edges.find({b, a});
      if (back != edges.end() && back->second > 0) {
        if (--back->second == 0) edges.erase(back);
      } else {
        ++edges[{a, b}];
      }
    }
  std::unordered_map<int, int> next;
  for (const auto& [e, count] : edges) {
    if (count != 1 || next.count(e.first)) return {};
    next[e.first] = e.second;
  }
  std::vector<Loop> loops;
  while (!next.empty()) {
    Loop loop;
    const int start = next.begin()->first;
    int v = start;
    do {
      const auto it = next.find(v);
      if (it == next.end()) return {};
      loop.push_back(welder.point(v));
      v = it->second;
      next.erase(it);
    } while (v != start);
    loops.push_back(std::move(loop));
  }
  return loops;
}

// Drops vertices where the boundary runs straight on (a meshed face's edge of 32 segments
// becomes one edge).
Loop mergeCollinear(const Loop& loop) {
  Loop out;
  const size_t m = loop.size();
  for (size_t k = 0; k < m; ++k) {
    const Vec3 d0 = loop[k] - loop[(k + m - 1) % m], d1 = loop[(k + 1) % m] - loop[k];
    const bool straight = d0.cross(d1).norm() <= 1e-12 * d0.norm() * d1.norm() && d0.dot(d1) > 0;
    if (!straight) out.push_back(loop[k]);
  }
  return out;
}

bool isConvex(const Loop& loop, const Vec3& n) {
  const size_t m = loop.size();
  if (m < 3) return false;
  for (size_t k = 0; k < m; ++k) {
    const Vec3 d0 = loop[(k + 1) % m] - loop[k], d1 = loop[(k + 2) % m] - loop[(k + 1) % m];
    if (n.dot(d0.cross(d1)) <= 1e-12 * d0.norm() * d1.norm()) return false;
  }
  return true;
}

void boundingBox(const std::vector<Loop>& loops, Vec3& lo, Vec3& hi) {
  lo = Vec3::Constant(1e300);
  hi = Vec3::Constant(-1e300);
  for (const Loop& l : loops)
    for (const Vec3& v : l) {
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
}

Loop asLoop(const std::array<Vec3, 3>& t) { return {t[0], t[1], t[2]}; }

// Merged loops of a group, and convex pieces: the merged loop itself when it is one convex
// polygon, the triangles otherwise.
void mergeGroup(const Group& g, double weld_tolerance, std::vector<Loop>& loops, std::vector<Loop>& pieces) {
  loops.clear();
  pieces.clear();
  if (g.triangles.size() > 1) {
    for (const Loop& l : boundaryLoops(g.triangles, weld_tolerance)) {
      Loop merged = mergeCollinear(l);
      if (merged.size() >= 3) loops.push_back(std::move(merged));
    }
  }
  // Separate convex outlines (no holes: every loop counter-clockwise) are their own pieces.
  const bool convex_outlines = !loops.empty() && std::all_of(loops.begin(), loops.end(), [&](const Loop& l) {
    return isConvex(l, g.normal) && signedArea(l, g.normal) > 0;
  });
  if (convex_outlines) {
    pieces = loops;
    return;
  }
  for (const auto& t : g.triangles) pieces.push_back(asLoop(t));
  if (loops.empty()) loops = pieces;
}

std::array<Vec3, 3> oriented(const Face& f, int side) {
  return side > 0 ? f.v : std::array<Vec3, 3>{f.v[0], f.v[2], f.v[1]};
}

}  // namespace

std::vector<Patch> buildPatches(const Scene& scene) {
  const double extent = std::max(scene.extent(), 1e-300);
  std::map<PlaneKey, Group> groups;
  std::map<PlaneKey, int> node_of;
  for (const Face& f : scene.faces())
    for (int side : {+1, -1}) {
      const int node = side > 0 ? f.front_node : f.back_node;
      const Vec3 n = side * f.normal;
      // Inactive sides group by side and plane; nodes by node and plane.
      const long tag = node >= 0 ? 2L * node : -1L - (side > 0 ? 0 : 1);
      const PlaneKey key = planeKey(tag, n, n.dot(f.v[0]), extent);
      Group& g = groups[key];
      if (g.triangles.empty()) g.normal = n;
      g.triangles.push_back(oriented(f, side));
      node_of[key] = node;
    }
  std::vector<Patch> patches;
  patches.reserve(groups.size());
  for (const auto& [key, g] : groups) {
    Patch p;
    p.node = node_of[key];
    p.region.normal = g.normal;
    mergeGroup(g, 1e-9 * extent, p.region.loops, p.pieces);
    for (const Loop& piece : p.pieces) p.area_m2 += signedArea(piece, g.normal);
    p.offset = g.normal.dot(g.triangles[0][0]);
    p.faces = static_cast<int>(g.triangles.size());
    boundingBox(p.pieces, p.lo, p.hi);
    patches.push_back(std::move(p));
  }
  return patches;
}

bool allBehind(const std::vector<Vec3>& points, const Patch& plane, double tol) {
  for (const Vec3& v : points)
    if (plane.region.normal.dot(v) - plane.offset > tol) return false;
  return true;
}

bool anyBehind(const std::vector<Vec3>& points, const Patch& plane, double tol) {
  for (const Vec3& v : points)
    if (plane.region.normal.dot(v) - plane.offset < -tol) return true;
  return false;
}

std::vector<Occluder> buildOccluders(const Scene& scene) {
  const double extent = std::max(scene.extent(), 1e-300);
  std::map<PlaneKey, Group> groups;
  for (const Face& f : scene.faces()) {
    // One orientation per plane: the normal's first clearly non-zero component positive.
    Vec3 n = f.normal;
    const int axis = std::abs(n.x()) > 1e-9 ? 0 : (std::abs(n.y()) > 1e-9 ? 1 : 2);
    const int side = n[axis] > 0 ? +1 : -1;
    n *= side;
    Group& g = groups[planeKey(0, n, n.dot(f.v[0]), extent)];
    if (g.triangles.empty()) g.normal = n;
    g.triangles.push_back(oriented(f, side));
  }
  std::vector<Occluder> out;
  for (const auto& [key, g] : groups) {
    std::vector<Loop> loops, pieces;
    mergeGroup(g, 1e-9 * extent, loops, pieces);
    for (Loop& piece : pieces) {
      Occluder o;
      o.normal = g.normal;
      o.offset = g.normal.dot(piece[0]);
      boundingBox({piece}, o.lo, o.hi);
      o.centre = Vec3::Zero();
      for (const Vec3& v : piece) o.centre += v;
      o.centre /= double(piece.size());
      o.polygon = std::move(piece);
      out.push_back(std::move(o));
    }
  }
  return out;
}

std::vector<Vec3> pointsOf(const Patch& p) {
  std::vector<Vec3> out;
  for (const Loop& l : p.pieces) out.insert(out.end(), l.begin(), l.end());
  return out;
}

std::vector<Loop> clippedPieces(const Patch& a, const Patch& b) {
  std::vector<Loop> out;
  const Vec3 point = b.offset * b.region.normal;
  for (const Loop& piece : a.pieces) {
    Loop kept = clipToHalfSpace(piece, point, b.region.normal);
    if (!kept.empty()) out.push_back(std::move(kept));
  }
  return out;
}

}  // namespace radnet::geometry
