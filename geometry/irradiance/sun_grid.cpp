#include "geometry/irradiance/sun_grid.hpp"

#include "geometry/irradiance/queries.hpp"
#include "geometry/rays/sampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace radnet::geometry {
namespace {

// One triangle projected onto the grid plane: cell-unit coordinates (x, y), depth
// towards the Sun w = p·d (larger: nearer the Sun), and the node of its sun-facing side.
struct Projected {
  double x[3], y[3], w[3];
  double twice_area;  // signed, cell units²
  int node;           // −1: the sun-facing side is inactive (it shadows, belongs to no node)
  int x0, x1, y0, y1;  // covered cell range, inclusive
};

// The grid: cell (a, b) holds one ray through a jittered point of the cell.
struct Grid {
  double u0 = 0, v0 = 0, h = 1;
  int nx = 0, ny = 0;
  std::uint64_t seed = 1;
  // The cell's jittered point in cell units: a + ξ, b + η.
  void point(int a, int b, double& x, double& y) const {
    const std::uint64_t r = mixSeed(seed, static_cast<std::uint64_t>(a), static_cast<std::uint64_t>(b));
    x = a + double(r >> 40) * 0x1p-24;
    y = b + double(r & 0xffffffu) * 0x1p-24;
  }
};

// Barycentric weights of (x, y) in t; true when inside (edges shared by two triangles go
// to one or the other by the sign test: a jittered point lies on one with probability 0).
bool inside(const Projected& t, double x, double y, double b[3]) {
  b[0] = (t.x[1] - x) * (t.y[2] - y) - (t.x[2] - x) * (t.y[1] - y);
  b[1] = (t.x[2] - x) * (t.y[0] - y) - (t.x[0] - x) * (t.y[2] - y);
  b[2] = (t.x[0] - x) * (t.y[1] - y) - (t.x[1] - x) * (t.y[0] - y);
  const double s = t.twice_area;
  if (s > 0 ? (b[0] < 0 || b[1] < 0 || b[2] < 0) : (b[0] > 0 || b[1] > 0 || b[2] > 0)) return false;
  for (int k = 0; k < 3; ++k) b[k] /= s;
  return true;
}

std::vector<Projected> project(const Scene& scene, const Vec3& d, const Vec3& e1, const Vec3& e2, Grid& g,
                               Eigen::VectorXd& facing) {
  std::vector<Projected> tris;
  double umin = std::numeric_limits<double>::max(), vmin = umin, umax = -umin, vmax = -umin;
  for (const Face& f : scene.faces())
    for (const Vec3& p : f.v) {
      umin = std::min(umin, p.dot(e1)), umax = std::max(umax, p.dot(e1));
      vmin = std::min(vmin, p.dot(e2)), vmax = std::max(vmax, p.dot(e2));
    }
  g.u0 = umin - 0.5 * g.h;
  g.v0 = vmin - 0.5 * g.h;
  g.nx = static_cast<int>(std::ceil((umax - g.u0) / g.h)) + 1;
  g.ny = static_cast<int>(std::ceil((vmax - g.v0) / g.h)) + 1;
  for (const Face& f : scene.faces()) {
    const double c = f.normal.dot(d);
    if (std::abs(c) < 1e-12) continue;  // edge-on: no projected area
    Projected t;
    t.node = c > 0 ? f.front_node : f.back_node;
    if (t.node >= 0) facing[t.node] += f.area_m2 * std::abs(c);
    for (int k = 0; k < 3; ++k) {
      t.x[k] = (f.v[k].dot(e1) - g.u0) / g.h;
      t.y[k] = (f.v[k].dot(e2) - g.v0) / g.h;
      t.w[k] = f.v[k].dot(d);
    }
    t.twice_area = (t.x[1] - t.x[0]) * (t.y[2] - t.y[0]) - (t.x[2] - t.x[0]) * (t.y[1] - t.y[0]);
    if (t.twice_area == 0) continue;
    t.x0 = std::max(0, static_cast<int>(std::floor(std::min({t.x[0], t.x[1], t.x[2]}))));
    t.x1 = std::min(g.nx - 1, static_cast<int>(std::floor(std::max({t.x[0], t.x[1], t.x[2]}))));
    t.y0 = std::max(0, static_cast<int>(std::floor(std::min({t.y[0], t.y[1], t.y[2]}))));
    t.y1 = std::min(g.ny - 1, static_cast<int>(std::floor(std::max({t.y[0], t.y[1], t.y[2]}))));
    tris.push_back(t);
  }
  return tris;
}

// The z-buffer: per cell the triangle nearest the Sun at its jittered point (−1: none).
// Rows are cut into bands, each band rasterises the triangles that reach it, so threads
// never share a cell; ties go to the lower triangle index (deterministic).
std::vector<int> zBuffer(const std::vector<Projected>& tris, const Grid& g) {
  constexpr int kBand = 32;
  const int bands = (g.ny + kBand - 1) / kBand;
  std::vector<std::vector<int>> in_band(static_cast<size_t>(bands));
  for (size_t k = 0; k < tris.size(); ++k)
    for (int b = tris[k].y0 / kBand; b <= tris[k].y1 / kBand; ++b) in_band[static_cast<size_t>(b)].push_back(int(k));
  std::vector<int> winner(static_cast<size_t>(g.nx) * static_cast<size_t>(g.ny), -1);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
#endif
  for (int b = 0; b < bands; ++b) {
    const int r0 = b * kBand, r1 = std::min(g.ny, r0 + kBand) - 1;
    std::vector<double> depth(static_cast<size_t>(g.nx) * kBand, -std::numeric_limits<double>::infinity());
    for (int k : in_band[static_cast<size_t>(b)]) {
      const Projected& t = tris[static_cast<size_t>(k)];
      for (int row = std::max(r0, t.y0); row <= std::min(r1, t.y1); ++row)
        for (int col = t.x0; col <= t.x1; ++col) {
          double x, y, w[3];
          g.point(col, row, x, y);
          if (!inside(t, x, y, w)) continue;
          const double z = w[0] * t.w[0] + w[1] * t.w[1] + w[2] * t.w[2];
          double& best = depth[static_cast<size_t>(row - r0) * static_cast<size_t>(g.nx) + static_cast<size_t>(col)];
          if (z > best) {
            best = z;
            winner[static_cast<size_t>(row) * static_cast<size_t>(g.nx) + static_cast<size_t>(col)] = k;
          }
        }
    }
  }
  return winner;
}

// Per node: crossings m (cells its sun-facing triangles cover), lit cells c, and the
// 4-neighbour pairs where the lit state flips (t) or the node's coverage ends (e), on a
// bitmap of the node's own cell box.
struct NodeCounts {
  std::int64_t m = 0, c = 0, t = 0, e = 0;
};

NodeCounts countNode(const std::vector<Projected>& tris, const std::vector<int>& mine, const std::vector<int>& winner,
                     const Grid& g, std::vector<unsigned char>& map) {
  NodeCounts out;
  int x0 = g.nx, x1 = -1, y0 = g.ny, y1 = -1;
  for (int k : mine) {
    const Projected& t = tris[static_cast<size_t>(k)];
    x0 = std::min(x0, t.x0), x1 = std::max(x1, t.x1), y0 = std::min(y0, t.y0), y1 = std::max(y1, t.y1);
  }
  if (x1 < x0 || y1 < y0) return out;
  const int w = x1 - x0 + 1, hgt = y1 - y0 + 1;
  map.assign(static_cast<size_t>(w) * static_cast<size_t>(hgt), 0);  // 0: not covered, 1: lit, 2: shadowed
  for (int k : mine) {
    const Projected& t = tris[static_cast<size_t>(k)];
    for (int row = t.y0; row <= t.y1; ++row)
      for (int col = t.x0; col <= t.x1; ++col) {
        double x, y, b[3];
        g.point(col, row, x, y);
        if (!inside(t, x, y, b)) continue;
        ++out.m;
        const bool lit = winner[static_cast<size_t>(row) * static_cast<size_t>(g.nx) + static_cast<size_t>(col)] == k;
        out.c += lit;
        unsigned char& s = map[static_cast<size_t>(row - y0) * static_cast<size_t>(w) + static_cast<size_t>(col - x0)];
        s = (s == 1 || lit) ? 1 : 2;  // a node covering a cell twice is lit there if either layer is
      }
  }
  auto pair = [&](unsigned char a, unsigned char b) {
    if (a == 0 && b == 0) return;
    if (a == 0 || b == 0) ++out.e;
    else if (a != b) ++out.t;
  };
  for (int row = 0; row < hgt; ++row)
    for (int col = 0; col < w; ++col) {
      const unsigned char s = map[static_cast<size_t>(row) * static_cast<size_t>(w) + static_cast<size_t>(col)];
      pair(s, col + 1 < w ? map[static_cast<size_t>(row) * static_cast<size_t>(w) + static_cast<size_t>(col + 1)] : 0);
      pair(s, row + 1 < hgt ? map[static_cast<size_t>(row + 1) * static_cast<size_t>(w) + static_cast<size_t>(col)] : 0);
      if (col == 0) pair(0, s);
      if (row == 0) pair(0, s);
    }
  return out;
}

// Each node's ratio estimate and σ from the z-buffer (SunlitArea::projected_m2 and
// stderr_m2); returns the nodes to shadow with their own rays instead.
std::vector<char> gridEstimates(const Scene& scene, const std::vector<Projected>& tris, const std::vector<int>& winner,
                                const Grid& g, const SunGridOptions& opt, SunlitArea& out) {
  const int n = static_cast<int>(scene.nodes().size());
  std::vector<std::vector<int>> by_node(static_cast<size_t>(n));
  for (size_t k = 0; k < tris.size(); ++k)
    if (tris[k].node >= 0) by_node[static_cast<size_t>(tris[k].node)].push_back(static_cast<int>(k));
  std::vector<char> small(static_cast<size_t>(n), 0);
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 4)
#endif
  for (int i = 0; i < n; ++i) {
    thread_local std::vector<unsigned char> map;
    if (out.facing_m2[i] <= 0) continue;
    const NodeCounts c = countNode(tris, by_node[static_cast<size_t>(i)], winner, g, map);
    const double area = scene.nodes()[static_cast<size_t>(i)].area_m2;
    if (c.m < opt.min_crossings && out.facing_m2[i] > opt.negligible_fraction * area) {
      small[static_cast<size_t>(i)] = 1;
      out.stderr_m2[i] = std::numeric_limits<double>::infinity();  // no grid estimate: the rays' wins
      continue;
    }
    if (c.m < opt.min_crossings) {  // edge-on and barely sampled: a binomial bound, or half ± all
      const double p = c.m > 0 ? double(c.c) / double(c.m) : 0.5;
      out.projected_m2[i] = out.facing_m2[i] * p;
      out.stderr_m2[i] = out.facing_m2[i] * (c.m > 0 ? std::sqrt(std::max(p * (1 - p), 0.25 / double(c.m)) / double(c.m))
                                                     : 0.5);
      continue;
    }
    const double p = double(c.c) / double(c.m);
    out.projected_m2[i] = out.facing_m2[i] * p;
    // Edge cells are Bernoulli trials (mean p(1−p) = 1/6 over the cell fraction): shadow
    // edges t; the node's own outline e enters the ratio through the shadowed part only.
    out.stderr_m2[i] = out.facing_m2[i] / double(c.m) * std::sqrt((double(c.t) + double(c.e) * p * (1 - p)) / 6.0);
    if (opt.max_relative_stderr > 0 && out.stderr_m2[i] > opt.max_relative_stderr * out.facing_m2[i])
      small[static_cast<size_t>(i)] = 1;
  }
  return small;
}

// The nodes the grid leaves cast their own shadow rays, doubled up to max_node_samples
// while a node's σ stays above the target; each keeps the estimate with the smaller σ.
void shadowByOwnRays(const RayCaster& caster, const Vec3& d, const SunGridOptions& opt, std::vector<char> todo,
                     SunlitArea& out) {
  const Eigen::Index n = out.projected_m2.size();
  for (int samples = opt.node_samples;; samples *= 2) {
    const LitArea rays = litArea(caster, d, samples, opt.seed, todo, opt.node_replicas);
    out.node_rays += rays.rays_cast;
    bool more = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      char& t = todo[static_cast<size_t>(i)];
      if (!t) continue;
      if (rays.stderr_m2[i] < out.stderr_m2[i]) {
        out.projected_m2[i] = rays.projected_m2[i];
        out.stderr_m2[i] = rays.stderr_m2[i];
      }
      t = opt.max_relative_stderr > 0 && out.stderr_m2[i] > opt.max_relative_stderr * out.facing_m2[i];
      more |= t != 0;
    }
    if (!more || 2LL * samples > opt.max_node_samples) break;
  }
}

}  // namespace

double sunGridSpacing(double area_m2, double relative_error) {
  return std::sqrt(area_m2) * std::pow(std::sqrt(6.0) * relative_error, 2.0 / 3.0);
}

SunlitArea sunlitArea(const RayCaster& caster, const Vec3& toward_sun, const SunGridOptions& opt) {
  if (!(opt.cell_m > 0) || !std::isfinite(opt.cell_m)) throw std::invalid_argument("sun grid spacing must be > 0");
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  const Vec3 d = toward_sun.normalized();
  const Vec3 e1 = d.unitOrthogonal(), e2 = d.cross(e1);
  SunlitArea out;
  out.projected_m2 = out.stderr_m2 = out.facing_m2 = Eigen::VectorXd::Zero(n);
  Grid g;
  g.seed = mixSeed(opt.seed, 0x5a9d);
  g.h = opt.cell_m;
  std::vector<Projected> tris;
  for (;;) {  // grow the spacing until the grid fits
    out.facing_m2.setZero();
    tris = project(scene, d, e1, e2, g, out.facing_m2);
    const double cells = double(g.nx) * double(g.ny);
    if (cells <= double(opt.max_cells)) break;
    g.h *= std::sqrt(cells / double(opt.max_cells)) * 1.01;
  }
  out.cell_m = g.h;
  out.cells = std::int64_t(g.nx) * g.ny;
  const std::vector<int> winner = zBuffer(tris, g);
  std::vector<char> small = gridEstimates(scene, tris, winner, g, opt, out);
  for (char s : small) out.sampled_nodes += s;
  if (out.sampled_nodes > 0) shadowByOwnRays(caster, d, opt, small, out);
  return out;
}

}  // namespace radnet::geometry
