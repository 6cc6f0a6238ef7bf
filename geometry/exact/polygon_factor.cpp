#include "geometry/exact/polygon_factor.hpp"

#include <array>
#include <cmath>

namespace radnet::geometry {
namespace {

// Gauss–Legendre on [0, 1]: 3 and 5 points (the pair gives the error estimate).
constexpr std::array<double, 3> kX3 = {0.1127016653792583, 0.5, 0.8872983346207417};
constexpr std::array<double, 3> kW3 = {0.2777777777777778, 0.4444444444444444, 0.2777777777777778};
constexpr std::array<double, 5> kX5 = {0.04691007703066800, 0.2307653449471585, 0.5, 0.7692346550528415,
                                       0.9530899229693320};
constexpr std::array<double, 5> kW5 = {0.1184634425280945, 0.2393143352496832, 0.2844444444444444,
                                       0.2393143352496832, 0.1184634425280945};
constexpr int kMaxDepth = 40;  // bisections of an outer edge: 2⁻⁴⁰ of its length

struct Edge {
  Vec3 a, u;  // start, unit direction
  double length = 0.0;
};

std::vector<Edge> edgesOf(const PlanarRegion& r) {
  std::vector<Edge> out;
  for (const Loop& loop : r.loops)
    for (size_t k = 0; k < loop.size(); ++k) {
      const Vec3 d = loop[(k + 1) % loop.size()] - loop[k];
      const double len = d.norm();
      if (len > 0) out.push_back({loop[k], d / len, len});
    }
  return out;
}

// ∫_0^L ln(|p − (a + t u)| / r_ref) dt in closed form; log_ref2 = ln r_ref².
double lineLogIntegral(const Vec3& p, const Edge& e, double log_ref2) {
  const Vec3 d = p - e.a;
  const double t0 = e.u.dot(d);
  const double h = d.cross(e.u).norm();
  auto primitive = [&](double x) {
    const double r2 = x * x + h * h;
    double v = -x;
    if (r2 > 0) v += 0.5 * x * (std::log(r2) - log_ref2);
    if (h > 0) v += h * std::atan(x / h);
    return v;
  };
  return primitive(e.length - t0) - primitive(-t0);
}

// The outer integrand at s along edge e: Σ_f (u_e·u_f) ∫_f ln(r/r_ref).
class OuterIntegrand {
 public:
  OuterIntegrand(const Edge& e, const std::vector<Edge>& q, double log_ref2) : e_(e), log_ref2_(log_ref2) {
    for (const Edge& f : q) {
      const double w = e.u.dot(f.u);
      if (std::abs(w) > 1e-15) terms_.push_back({&f, w});
    }
  }
  bool empty() const { return terms_.empty(); }
  double operator()(double s) {
    ++evaluations;
    const Vec3 p = e_.a + s * e_.u;
    double sum = 0.0;
    for (const auto& t : terms_) sum += t.weight * lineLogIntegral(p, *t.edge, log_ref2_);
    return sum;
  }
  long long evaluations = 0;

 private:
  struct Term {
    const Edge* edge;
    double weight;
  };
  const Edge& e_;
  double log_ref2_;
  std::vector<Term> terms_;
};

// Adaptive bisection with the (3, 5)-point Gauss pair; returns the 5-point value.
void adaptive(OuterIntegrand& g, double s0, double s1, double tol, int depth, double& value, double& error) {
  const double h = s1 - s0;
  double i3 = 0.0, i5 = 0.0;
  for (size_t k = 0; k < kX3.size(); ++k) i3 += kW3[k] * g(s0 + kX3[k] * h);
  for (size_t k = 0; k < kX5.size(); ++k) i5 += kW5[k] * g(s0 + kX5[k] * h);
  i3 *= h;
  i5 *= h;
  const double diff = std::abs(i5 - i3);
  if (diff <= tol || depth >= kMaxDepth) {
    value += i5;
    error += diff;
    return;
  }
  const double mid = 0.5 * (s0 + s1);
  adaptive(g, s0, mid, 0.5 * tol, depth + 1, value, error);
  adaptive(g, mid, s1, 0.5 * tol, depth + 1, value, error);
}

Vec3 centroidOf(const PlanarRegion& r) {
  Vec3 c = Vec3::Zero();
  int count = 0;
  for (const Loop& loop : r.loops)
    for (const Vec3& v : loop) {
      c += v;
      ++count;
    }
  return count > 0 ? Vec3(c / count) : c;
}

}  // namespace

FactorEstimate polygonExchangeArea(const PlanarRegion& p, const PlanarRegion& q, double tolerance) {
  FactorEstimate out;
  const std::vector<Edge> ep = edgesOf(p), eq = edgesOf(q);
  double perimeter = 0.0;
  for (const Edge& e : ep) perimeter += e.length;
  if (ep.empty() || eq.empty() || perimeter <= 0) return out;
  // ln r is taken relative to the centroid distance: Σ_e Σ_f (u_e·u_f) L_e L_f ln r_ref
  // vanishes on closed loops, and the terms left are of the size of the answer.
  const double r_ref = std::max((centroidOf(p) - centroidOf(q)).norm(), 1e-300);
  const double log_ref2 = 2.0 * std::log(r_ref);
  double sum = 0.0, err = 0.0;
  for (const Edge& e : ep) {
    OuterIntegrand g(e, eq, log_ref2);
    if (g.empty()) continue;
    adaptive(g, 0.0, e.length, 2.0 * M_PI * tolerance * e.length / perimeter, 0, sum, err);
    out.evaluations += g.evaluations;
  }
  // Both loops counter-clockwise about normals that face each other: the double contour
  // integral comes out as +2π A_P F_PQ.
  out.value = sum / (2.0 * M_PI);
  out.error = err / (2.0 * M_PI);
  return out;
}

double pointToConvexPolygon(const Vec3& point, const Vec3& n, const Loop& polygon) {
  const size_t m = polygon.size();
  if (m < 3) return 0.0;
  double sum = 0.0;
  for (size_t k = 0; k < m; ++k) {
    const Vec3 r0 = polygon[k] - point, r1 = polygon[(k + 1) % m] - point;
    const Vec3 cr = r0.cross(r1);
    const double crn = cr.norm();
    if (crn <= 1e-300) continue;  // an edge seen end-on subtends nothing
    sum += std::atan2(crn, r0.dot(r1)) * n.dot(cr) / crn;
  }
  // A loop counter-clockwise about a normal facing the point turns clockwise about n.
  return -sum / (2.0 * M_PI);
}

void splitByPlane(const Loop& polygon, const Vec3& m, double c, Loop& outside, Loop& inside) {
  outside.clear();
  inside.clear();
  const size_t count = polygon.size();
  for (size_t k = 0; k < count; ++k) {
    const Vec3& u = polygon[k];
    const Vec3& v = polygon[(k + 1) % count];
    const double du = m.dot(u) - c, dv = m.dot(v) - c;
    if (du >= 0) outside.push_back(u);
    if (du <= 0) inside.push_back(u);
    if ((du > 0 && dv < 0) || (du < 0 && dv > 0)) {
      const Vec3 x = u + (du / (du - dv)) * (v - u);
      outside.push_back(x);
      inside.push_back(x);
    }
  }
  if (outside.size() < 3) outside.clear();
  if (inside.size() < 3) inside.clear();
}

Loop clipToHalfSpace(const Loop& polygon, const Vec3& plane_point, const Vec3& plane_normal) {
  Loop keep, drop;
  splitByPlane(polygon, plane_normal, plane_normal.dot(plane_point), keep, drop);
  return keep;
}

double signedArea(const Loop& loop, const Vec3& n) {
  Vec3 twice = Vec3::Zero();
  for (size_t k = 0; k < loop.size(); ++k) twice += loop[k].cross(loop[(k + 1) % loop.size()]);
  return 0.5 * n.dot(twice);
}

}  // namespace radnet::geometry
