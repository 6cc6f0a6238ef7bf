#include "geometry/irradiance/sun_clip.hpp"

#include "geometry/scene/open_sides.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace radnet::geometry {
namespace {

struct P2 {
  double x, y;
};
using Polygon = std::vector<P2>;  // convex, counter-clockwise as seen from the Sun

// One triangle seen from the Sun: its corners on the plane normal to the Sun (counter-
// clockwise), their box there, its depths towards the Sun and the node of its sun-facing side.
struct Flat {
  std::array<P2, 3> p;
  double umin, umax, vmin, vmax;
  double wmin, wmax;  // lowest and highest corner along the Sun's direction, m
  double projected;   // area of p: ∫ |n·d| dA, m²
  int face;
  int node;        // the sun-facing side's, −1: inactive (it shadows, receives nothing)
  double facing;   // n·d's sign: +1 front side towards the Sun, −1 back side
};

double cross(const P2& a, const P2& b, const P2& p) { return (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x); }

double area(const Polygon& poly) {
  double twice = 0.0;
  for (size_t i = 0, m = poly.size(); i < m; ++i) {
    const P2& a = poly[i];
    const P2& b = poly[(i + 1) % m];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * twice;
}

std::vector<Flat> project(const Scene& scene, const Vec3& d, const Vec3& e1, const Vec3& e2) {
  std::vector<Flat> flats;
  const auto& faces = scene.faces();
  flats.reserve(faces.size());
  for (size_t k = 0; k < faces.size(); ++k) {
    const Face& f = faces[k];
    const double c = f.normal.dot(d);
    if (std::abs(c) < 1e-12) continue;  // edge-on: no projection, no shadow
    Flat t;
    t.face = static_cast<int>(k);
    t.facing = c > 0 ? 1.0 : -1.0;
    t.node = c > 0 ? f.front_node : f.back_node;
    t.wmin = std::numeric_limits<double>::max(), t.wmax = -t.wmin;
    for (int j = 0; j < 3; ++j) {
      const Vec3& v = f.v[static_cast<size_t>(c > 0 ? j : 2 - j)];  // counter-clockwise seen from the Sun
      t.p[static_cast<size_t>(j)] = {v.dot(e1), v.dot(e2)};
      t.wmin = std::min(t.wmin, v.dot(d)), t.wmax = std::max(t.wmax, v.dot(d));
    }
    t.umin = std::min({t.p[0].x, t.p[1].x, t.p[2].x}), t.umax = std::max({t.p[0].x, t.p[1].x, t.p[2].x});
    t.vmin = std::min({t.p[0].y, t.p[1].y, t.p[2].y}), t.vmax = std::max({t.p[0].y, t.p[1].y, t.p[2].y});
    t.projected = 0.5 * cross(t.p[0], t.p[1], t.p[2]);
    if (!(t.projected > 0)) continue;  // round-off turned it edge-on
    flats.push_back(t);
  }
  return flats;
}

// A uniform grid over the projections: cell → the triangles whose box reaches it.
struct Bins {
  double u0 = 0, v0 = 0, h = 1;
  int nx = 1, ny = 1;
  std::vector<int> start, items;  // each cell's items nearest the Sun first ...
  std::vector<double> item_wmax;  // ... by their highest corner, kept beside them
  void cells(const Flat& t, int& x0, int& x1, int& y0, int& y1) const {
    x0 = std::clamp(static_cast<int>((t.umin - u0) / h), 0, nx - 1);
    x1 = std::clamp(static_cast<int>((t.umax - u0) / h), 0, nx - 1);
    y0 = std::clamp(static_cast<int>((t.vmin - v0) / h), 0, ny - 1);
    y1 = std::clamp(static_cast<int>((t.vmax - v0) / h), 0, ny - 1);
  }
};

// Cells of about twice the median triangle box (a few large panels then span many cells
// while the many small facets of a dish or a mast share few), grown while the entries
// would exceed 16 a triangle or the cells 4 M.
Bins binFlats(const std::vector<Flat>& flats) {
  Bins b;
  if (flats.empty()) return b;
  double umin = std::numeric_limits<double>::max(), vmin = umin, umax = -umin, vmax = -umin;
  std::vector<double> side;
  side.reserve(flats.size());
  for (const Flat& t : flats) {
    umin = std::min(umin, t.umin), umax = std::max(umax, t.umax);
    vmin = std::min(vmin, t.vmin), vmax = std::max(vmax, t.vmax);
    side.push_back(std::sqrt((t.umax - t.umin) * (t.vmax - t.vmin)));
  }
  std::nth_element(side.begin(), side.begin() + static_cast<std::ptrdiff_t>(side.size() / 2), side.end());
  const double span = std::max({umax - umin, vmax - vmin, 1e-9});
  b.h = std::max({2.0 * side[side.size() / 2], span / 2048.0, 1e-12});
  for (;; b.h *= 1.5) {
    double entries = 0.0;
    for (const Flat& t : flats) entries += (std::floor((t.umax - t.umin) / b.h) + 2) * (std::floor((t.vmax - t.vmin) / b.h) + 2);
    if (entries <= 16.0 * double(flats.size()) && ((umax - umin) / b.h + 1) * ((vmax - vmin) / b.h + 1) <= 4e6) break;
  }
  b.u0 = umin, b.v0 = vmin;
  b.nx = static_cast<int>((umax - umin) / b.h) + 1, b.ny = static_cast<int>((vmax - vmin) / b.h) + 1;
  b.start.assign(static_cast<size_t>(b.nx) * static_cast<size_t>(b.ny) + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill;
    if (pass == 1) {
      for (size_t c = 1; c < b.start.size(); ++c) b.start[c] += b.start[c - 1];
      b.items.resize(static_cast<size_t>(b.start.back()));
      fill.assign(b.start.begin(), b.start.end() - 1);
    }
    for (size_t k = 0; k < flats.size(); ++k) {
      int x0, x1, y0, y1;
      b.cells(flats[k], x0, x1, y0, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const size_t c = static_cast<size_t>(y) * static_cast<size_t>(b.nx) + static_cast<size_t>(x);
          if (pass == 0) ++b.start[c + 1];
          else b.items[static_cast<size_t>(fill[c]++)] = static_cast<int>(k);
        }
    }
  }
  b.item_wmax.resize(b.items.size());
  for (size_t c = 0; c + 1 < b.start.size(); ++c) {
    const auto first = b.items.begin() + b.start[c], last = b.items.begin() + b.start[c + 1];
    std::sort(first, last, [&](int i, int j) { return flats[size_t(i)].wmax > flats[size_t(j)].wmax || (flats[size_t(i)].wmax == flats[size_t(j)].wmax && i < j); });
    for (int i = b.start[c]; i < b.start[c + 1]; ++i) b.item_wmax[size_t(i)] = flats[size_t(b.items[size_t(i)])].wmax;
  }
  return b;
}

// The part of occluder o in front of receiver r's plane (towards the Sun), projected:
// empty when none of it is. Corners within `tol` of the plane count as on it; an occluder
// reaching behind the plane is cut at the plane itself, one touching it (an edge shared
// with r, a wall standing on it) is kept whole, so the seam it closes stays closed.
bool inFront(const Face& r, const Flat& rt, const Face& o, const Flat& ot, double tol, Polygon& out) {
  std::array<double, 3> s;
  bool front = false, behind = false;
  for (int j = 0; j < 3; ++j) {
    const Vec3& v = o.v[static_cast<size_t>(ot.facing > 0 ? j : 2 - j)];  // ot.p's order
    s[static_cast<size_t>(j)] = (v - r.v[0]).dot(r.normal) * rt.facing;
    front |= s[static_cast<size_t>(j)] > tol;
    behind |= s[static_cast<size_t>(j)] < -tol;
  }
  out.clear();
  if (!front) return false;
  if (!behind) {
    out.assign(ot.p.begin(), ot.p.end());
    return true;
  }
  for (int j = 0; j < 3; ++j) {
    const int k = (j + 1) % 3;
    const double sj = s[static_cast<size_t>(j)], sk = s[static_cast<size_t>(k)];
    const P2& a = ot.p[static_cast<size_t>(j)];
    const P2& b = ot.p[static_cast<size_t>(k)];
    if (sj >= 0) out.push_back(a);
    if ((sj > 0 && sk < 0) || (sj < 0 && sk > 0)) {
      const double t = sj / (sj - sk);
      out.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  return out.size() >= 3 && area(out) > 0;
}

// Whether an edge of convex `occluder` leaves all of `piece` outside (on its right): then
// they do not overlap. Only the occluder's edges are asked, and only those longer than
// `min_edge_m`: a piece's edges (or a clipped occluder's) can be round-off short, and a
// direction from round-off would separate what overlaps. A missed separation costs only
// a needless cut.
bool separated(const Polygon& occluder, const Polygon& piece, double min_edge_m) {
  for (size_t i = 0, m = occluder.size(); i < m; ++i) {
    const P2& e0 = occluder[i];
    const P2& e1 = occluder[(i + 1) % m];
    const double dx = e1.x - e0.x, dy = e1.y - e0.y;
    if (dx * dx + dy * dy <= min_edge_m * min_edge_m) continue;
    bool all_right = true;
    for (const P2& p : piece)
      if (cross(e0, e1, p) > 0) {
        all_right = false;
        break;
      }
    if (all_right) return true;
  }
  return false;
}

// Whether the projections of two triangles are apart (an edge of either separates them;
// edges shorter than `min_edge_m` are not asked): most candidates whose boxes overlap, long
// thin CAD triangles above all, are settled here before any clipping.
bool trianglesApart(const Flat& a, const Flat& b, double min_edge_m) {
  const auto apart = [&](const Flat& e, const Flat& q) {
    for (int i = 0; i < 3; ++i) {
      const P2& e0 = e.p[static_cast<size_t>(i)];
      const P2& e1 = e.p[static_cast<size_t>((i + 1) % 3)];
      const double dx = e1.x - e0.x, dy = e1.y - e0.y;
      if (dx * dx + dy * dy <= min_edge_m * min_edge_m) continue;
      if (cross(e0, e1, q.p[0]) <= 0 && cross(e0, e1, q.p[1]) <= 0 && cross(e0, e1, q.p[2]) <= 0) return true;
    }
    return false;
  };
  return apart(a, b) || apart(b, a);
}

// Appends p unless it repeats the last corner (a corner on the line comes once).
void add(Polygon& poly, const P2& p) {
  if (poly.empty() || poly.back().x != p.x || poly.back().y != p.y) poly.push_back(p);
}

// Splits convex `piece` along the directed line a → b: `left` the part on its left
// (inside a counter-clockwise occluder), `right` the rest.
void split(const Polygon& piece, const P2& a, const P2& b, Polygon& left, Polygon& right) {
  left.clear(), right.clear();
  const size_t m = piece.size();
  double fp = cross(a, b, piece[0]);
  for (size_t i = 0; i < m; ++i) {
    const P2& p = piece[i];
    const P2& q = piece[(i + 1) % m];
    const double fq = cross(a, b, q);
    if (fp >= 0) add(left, p);
    if (fp <= 0) add(right, p);
    if ((fp > 0 && fq < 0) || (fp < 0 && fq > 0)) {
      const double t = fp / (fp - fq);
      const P2 x{p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
      add(left, x), add(right, x);
    }
    fp = fq;
  }
}

struct Scratch {
  std::vector<int> stamp;
  std::vector<Polygon> pieces, next;
  Polygon occluder, inside, outside;
};

// Removes convex `occluder` from the lit pieces: each piece it overlaps is cut along the
// occluder's edges, the parts outside kept, the part inside dropped. Parts below `sliver`
// (m²) are dropped too and added to `dropped`; `min_edge_m` as in separated().
void subtract(Scratch& s, double sliver, double min_edge_m, double& dropped) {
  const Polygon& c = s.occluder;
  s.next.clear();
  for (Polygon& piece : s.pieces) {
    if (separated(c, piece, min_edge_m)) {
      s.next.push_back(std::move(piece));
      continue;
    }
    for (size_t i = 0, m = c.size(); i < m && piece.size() >= 3; ++i) {
      split(piece, c[i], c[(i + 1) % m], s.inside, s.outside);
      if (s.outside.size() >= 3) {
        const double a = area(s.outside);
        if (a > sliver) s.next.push_back(s.outside);
        else dropped += std::max(a, 0.0);
      }
      piece.swap(s.inside);
    }
  }
  s.pieces.swap(s.next);
}

constexpr double kRoundOffWidth = 4096 * std::numeric_limits<double>::epsilon();  // relative to coord_m

// Lit projection of flat k, m²; `dropped` gets the slivers' area, `pairs` the occluders
// clipped. `coord_m`: the largest coordinate magnitude, the scale of round-off.
double litProjection(const Scene& scene, const std::vector<Flat>& flats, const Bins& bins, int k, double tol,
                     double coord_m, double sliver_fraction, Scratch& s, double& dropped, std::int64_t& pairs) {
  const Flat& r = flats[static_cast<size_t>(k)];
  const Face& rf = scene.faces()[static_cast<size_t>(r.face)];
  s.pieces.assign(1, Polygon(r.p.begin(), r.p.end()));
  // Round-off slivers are as wide as a few thousand ulps of the coordinates, whatever the
  // triangle's projection (one seen nearly edge-on has little area but long edges).
  const double diameter = std::hypot(r.umax - r.umin, r.vmax - r.vmin);
  const double sliver = std::max(sliver_fraction * r.projected, kRoundOffWidth * coord_m * diameter);
  int x0, x1, y0, y1;
  bins.cells(r, x0, x1, y0, y1);
  for (int y = y0; y <= y1 && !s.pieces.empty(); ++y)
    for (int x = x0; x <= x1 && !s.pieces.empty(); ++x) {
      const size_t c = static_cast<size_t>(y) * static_cast<size_t>(bins.nx) + static_cast<size_t>(x);
      for (int i = bins.start[c]; i < bins.start[c + 1] && !s.pieces.empty(); ++i) {
        if (bins.item_wmax[static_cast<size_t>(i)] <= r.wmin) break;  // the rest lie wholly below r's lowest point
        const int j = bins.items[static_cast<size_t>(i)];
        if (j == k || s.stamp[static_cast<size_t>(j)] == k) continue;
        s.stamp[static_cast<size_t>(j)] = k;
        const Flat& o = flats[static_cast<size_t>(j)];
        if (o.umax <= r.umin || o.umin >= r.umax || o.vmax <= r.vmin || o.vmin >= r.vmax) continue;
        if (trianglesApart(r, o, tol)) continue;
        if (!inFront(rf, r, scene.faces()[static_cast<size_t>(o.face)], o, tol, s.occluder)) continue;
        ++pairs;
        subtract(s, sliver, tol, dropped);
      }
    }
  if (pairs == 0) return r.projected;
  double lit = 0.0;
  for (const Polygon& piece : s.pieces) lit += area(piece);
  return std::min(lit, r.projected);
}

}  // namespace

SunlitArea exactSunlitArea(const Scene& scene, const Vec3& toward_sun, const ExactSunOptions& options) {
  const int n = static_cast<int>(scene.nodes().size());
  const Vec3 d = toward_sun.normalized();
  const Vec3 e1 = d.unitOrthogonal(), e2 = d.cross(e1);  // (e1, e2, d) right-handed
  SunlitArea out;
  out.projected_m2 = out.stderr_m2 = out.facing_m2 = Eigen::VectorXd::Zero(n);
  const std::vector<Flat> flats = project(scene, d, e1, e2);
  const Bins bins = binFlats(flats);
  const double tol = 1e-9 * scene.extent();  // corners this close to a plane lie on it
  double coord_m = 0.0;
  for (const Face& f : scene.faces())
    for (const Vec3& v : f.v) coord_m = std::max(coord_m, v.cwiseAbs().maxCoeff());
  const int m = static_cast<int>(flats.size());
  const std::vector<std::uint8_t>* open =
      options.open_sides && options.open_sides->size() == scene.faces().size() ? options.open_sides : nullptr;
  std::vector<double> lit(static_cast<size_t>(m), 0.0), dropped(static_cast<size_t>(m), 0.0);
  std::int64_t pairs = 0;
  // Inside a parallel loop (a sweep's positions, orbits/direct_loads) on its own thread.
#ifdef _OPENMP
#pragma omp parallel reduction(+ : pairs) if (!omp_in_parallel())
#endif
  {
    Scratch s;
    s.stamp.assign(static_cast<size_t>(m), -1);
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 64)
#endif
    for (int k = 0; k < m; ++k) {
      const Flat& flat = flats[static_cast<size_t>(k)];
      if (flat.node < 0) continue;
      if (open && ((*open)[static_cast<size_t>(flat.face)] & (flat.facing > 0 ? kFrontOpen : kBackOpen))) {
        lit[static_cast<size_t>(k)] = flat.projected;  // nothing can be in front of it
        continue;
      }
      std::int64_t clipped = 0;
      lit[static_cast<size_t>(k)] = litProjection(scene, flats, bins, k, tol, coord_m, options.sliver_fraction, s,
                                                  dropped[static_cast<size_t>(k)], clipped);
      pairs += clipped;
    }
  }
  for (int k = 0; k < m; ++k) {  // in face order: the sums do not depend on the threads
    const Flat& t = flats[static_cast<size_t>(k)];
    if (t.node < 0) continue;
    const Face& f = scene.faces()[static_cast<size_t>(t.face)];
    out.facing_m2[t.node] += f.area_m2 * std::abs(f.normal.dot(d));
    out.projected_m2[t.node] += lit[static_cast<size_t>(k)];
    out.stderr_m2[t.node] += dropped[static_cast<size_t>(k)];
  }
  out.projected_m2 = out.projected_m2.cwiseMin(out.facing_m2);
  out.occluding_pairs = pairs;
  return out;
}

}  // namespace radnet::geometry
