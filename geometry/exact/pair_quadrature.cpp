#include "geometry/exact/pair_quadrature.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace radnet::geometry {
namespace {

// A patch whose order-2 rule has more points than this goes to the contour integral: its
// pairs would cost more here than there (a merged patch of many triangles).
constexpr int kMaxPoints = 36;

// The next term of order 0+, taken as kFourthOrder ρ² |I_0| with ρ = (tr M_P + tr M_Q) / r²
// the patches' spread against their distance (the kernel's fourth derivatives over its value
// go as r⁻⁴, the patches' fourth moments as their second squared): added to |T| so that a
// Taylor term that cancels (|T| ≪ its parts) is not taken for a small error. The constant is
// measured, not derived: on the 8 × 8-cell room against the contour integral the largest
// fourth-order error is 6.7 ρ² |I_0| (tests/test_pair_quadrature.cpp checks the coverage).
constexpr double kFourthOrder = 8.0;

// Gauss–Legendre on [0, 1].
constexpr std::array<double, 2> kG2x = {0.2113248654051871, 0.7886751345948129};
constexpr std::array<double, 2> kG2w = {0.5, 0.5};
constexpr std::array<double, 3> kG3x = {0.1127016653792583, 0.5, 0.8872983346207417};
constexpr std::array<double, 3> kG3w = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};

// Triangle rules as (barycentric of the 2nd vertex, of the 3rd, weight share).
struct TrianglePoint {
  double b1, b2, w;
};
// Degree 2: three interior points (Strang & Fix).
constexpr std::array<TrianglePoint, 3> kTri3 = {{{1.0 / 6, 1.0 / 6, 1.0 / 3},
                                                 {2.0 / 3, 1.0 / 6, 1.0 / 3},
                                                 {1.0 / 6, 2.0 / 3, 1.0 / 3}}};
// Degree 4: Dunavant (1985), 6 points.
constexpr double kA1 = 0.445948490915965, kW1 = 0.223381589678011;
constexpr double kA2 = 0.091576213509771, kW2 = 0.109951743655322;
constexpr std::array<TrianglePoint, 6> kTri6 = {{{kA1, kA1, kW1},
                                                 {1 - 2 * kA1, kA1, kW1},
                                                 {kA1, 1 - 2 * kA1, kW1},
                                                 {kA2, kA2, kW2},
                                                 {1 - 2 * kA2, kA2, kW2},
                                                 {kA2, 1 - 2 * kA2, kW2}}};

bool isParallelogram(const Loop& l) {
  if (l.size() != 4) return false;
  const double size = (l[2] - l[0]).norm() + (l[3] - l[1]).norm();
  return (l[0] + l[2] - l[1] - l[3]).norm() <= 1e-12 * size;
}

// cos θ_P cos θ_Q / (π r²) between x (normal np) and y (normal nq), facing each other.
inline double kernel(double rx, double ry, double rz, const Vec3& np, const Vec3& nq) {
  const double r2 = rx * rx + ry * ry + rz * rz;
  const double cp = std::max(np.x() * rx + np.y() * ry + np.z() * rz, 0.0);
  const double cq = std::max(-(nq.x() * rx + nq.y() * ry + nq.z() * rz), 0.0);
  return cp * cq / (M_PI * r2 * r2);
}

}  // namespace

PatchRules::PatchRules(const std::vector<Patch>& patches) {
  order1_.start.push_back(0);
  order2_.start.push_back(0);
  for (const Patch& p : patches) addRules(p);
}

void PatchRules::addRules(const Patch& patch) {
  auto put = [](Points& rule, const Vec3& x, double w) {
    rule.x.push_back(x.x());
    rule.y.push_back(x.y());
    rule.z.push_back(x.z());
    rule.w.push_back(w);
  };
  Vec3 moment = Vec3::Zero();
  double area = 0.0;
  for (const Loop& l : patch.pieces) {
    if (isParallelogram(l)) {
      const Vec3 u = l[1] - l[0], v = l[3] - l[0];
      const double a = u.cross(v).norm();
      for (size_t i = 0; i < kG2x.size(); ++i)
        for (size_t j = 0; j < kG2x.size(); ++j) put(order1_, l[0] + kG2x[i] * u + kG2x[j] * v, a * kG2w[i] * kG2w[j]);
      for (size_t i = 0; i < kG3x.size(); ++i)
        for (size_t j = 0; j < kG3x.size(); ++j) put(order2_, l[0] + kG3x[i] * u + kG3x[j] * v, a * kG3w[i] * kG3w[j]);
      moment += a * (l[0] + 0.5 * (u + v));
      area += a;
      continue;
    }
    for (size_t k = 1; k + 1 < l.size(); ++k) {  // fan of a convex piece
      const Vec3 u = l[k] - l[0], v = l[k + 1] - l[0];
      const double a = 0.5 * u.cross(v).norm();
      for (const TrianglePoint& t : kTri3) put(order1_, l[0] + t.b1 * u + t.b2 * v, a * t.w);
      for (const TrianglePoint& t : kTri6) put(order2_, l[0] + t.b1 * u + t.b2 * v, a * t.w);
      moment += a * (l[0] + (u + v) / 3.0);
      area += a;
    }
  }
  order1_.start.push_back(static_cast<int>(order1_.w.size()));
  order2_.start.push_back(static_cast<int>(order2_.w.size()));
  const Vec3 c = area > 0 ? Vec3(moment / area) : Vec3::Zero();
  // The second moment about the centroid per unit area, from the order-2 points: exact, the
  // rules being exact for quadratics.
  Spread spread{};
  for (size_t k = size_t(order2_.start[order2_.start.size() - 2]); k < order2_.w.size(); ++k) {
    const double w = area > 0 ? order2_.w[k] / area : 0.0;
    const double dx = order2_.x[k] - c.x(), dy = order2_.y[k] - c.y(), dz = order2_.z[k] - c.z();
    spread.xx += w * dx * dx, spread.yy += w * dy * dy, spread.zz += w * dz * dz;
    spread.xy += w * dx * dy, spread.xz += w * dx * dz, spread.yz += w * dy * dz;
  }
  double radius = 0.0;
  for (const Loop& l : patch.pieces)
    for (const Vec3& v : l) radius = std::max(radius, (v - c).norm());
  centroid_.push_back(c);
  normal_.push_back(patch.region.normal);
  area_.push_back(area);
  radius_.push_back(radius);
  spread_.push_back(spread);
  const size_t id = centroid_.size() - 1;
  usable_.push_back(area > 0 && order2_.start[id + 1] - order2_.start[id] <= kMaxPoints);
}

double PatchRules::product(const Points& rule, size_t p, size_t q) const {
  const Vec3 &np = normal_[p], &nq = normal_[q];
  const int q0 = rule.start[q], q1 = rule.start[q + 1];
  double sum = 0.0;
  for (int i = rule.start[p]; i < rule.start[p + 1]; ++i) {
    const double xi = rule.x[size_t(i)], yi = rule.y[size_t(i)], zi = rule.z[size_t(i)];
    double inner = 0.0;
    for (int j = q0; j < q1; ++j)
      inner += rule.w[size_t(j)] * kernel(rule.x[size_t(j)] - xi, rule.y[size_t(j)] - yi, rule.z[size_t(j)] - zi, np, nq);
    sum += rule.w[size_t(i)] * inner;
  }
  return sum;
}

double PatchRules::centroidValue(size_t p, size_t q) const {
  const Vec3 r = centroid_[q] - centroid_[p];
  return area_[p] * area_[q] * kernel(r.x(), r.y(), r.z(), normal_[p], normal_[q]);
}

double PatchRules::secondOrderTerm(size_t p, size_t q) const {
  // With r = c_Q − c_P, n = n_P, m = −n_Q, a = n·r, b = m·r, s = r·r the kernel is
  // k = a b / (π s²) and its Hessian
  //   π H = s⁻² (n mᵀ + m nᵀ) − 4 s⁻³ ((b n + a m) rᵀ + r (b n + a m)ᵀ + a b I) + 24 a b s⁻⁴ r rᵀ;
  // the first-order terms vanish about the centroids, and the second-order one integrates
  // to A_P A_Q ½ tr(H (M_P + M_Q)), M the patches' second moments about their centroids.
  // Written out in scalars: one pair's worth is ~60 flops, less than the 16 kernel values of
  // order 1 only when nothing is spilled.
  const Spread &sp = spread_[p], &sq = spread_[q];
  const double xx = sp.xx + sq.xx, yy = sp.yy + sq.yy, zz = sp.zz + sq.zz;
  const double xy = sp.xy + sq.xy, xz = sp.xz + sq.xz, yz = sp.yz + sq.yz;
  const Vec3 r = centroid_[q] - centroid_[p];
  const Vec3& n = normal_[p];
  const double mx = -normal_[q].x(), my = -normal_[q].y(), mz = -normal_[q].z();
  const double rx = r.x(), ry = r.y(), rz = r.z();
  // M r and M m
  const double sr_x = xx * rx + xy * ry + xz * rz, sr_y = xy * rx + yy * ry + yz * rz, sr_z = xz * rx + yz * ry + zz * rz;
  const double sm_x = xx * mx + xy * my + xz * mz, sm_y = xy * mx + yy * my + yz * mz, sm_z = xz * mx + yz * my + zz * mz;
  const double a = n.x() * rx + n.y() * ry + n.z() * rz, b = mx * rx + my * ry + mz * rz;
  const double inv_s = 1.0 / (rx * rx + ry * ry + rz * rz);
  const double n_sm = n.x() * sm_x + n.y() * sm_y + n.z() * sm_z;
  const double n_sr = n.x() * sr_x + n.y() * sr_y + n.z() * sr_z, m_sr = mx * sr_x + my * sr_y + mz * sr_z;
  const double r_sr = rx * sr_x + ry * sr_y + rz * sr_z;
  const double trace =
      inv_s * inv_s *
      (2 * n_sm + inv_s * (-4 * (2 * b * n_sr + 2 * a * m_sr + a * b * (xx + yy + zz)) + 24 * a * b * r_sr * inv_s));
  return area_[p] * area_[q] * (0.5 / M_PI) * trace;
}

FactorEstimate PatchRules::exchangeArea(size_t p, size_t q, double absolute_target, double relative_target,
                                        bool& found) const {
  found = false;
  FactorEstimate out;
  const double centroid = centroidValue(p, q);
  out.value = centroid;
  out.evaluations = 1;
  const double distance = (centroid_[q] - centroid_[p]).norm();
  if (!usable(p) || !usable(q) || radius_[p] + radius_[q] >= kNearRatio * distance) return out;
  auto met = [&] { return out.error <= std::max(absolute_target, relative_target * out.value); };
  // Order 0+: the Taylor term is the centroid value's error to leading order, reported with
  // the fourth-order bound as the error of their sum.
  const double term = secondOrderTerm(p, q);
  out.value = centroid + term;
  const double spread = (spread_[p].trace() + spread_[q].trace()) / (distance * distance);  // ρ
  out.error = std::abs(term) + kFourthOrder * spread * spread * std::abs(centroid);
  if (met()) {
    found = true;
    return out;
  }
  double lower = centroid;
  for (const Points* rule : {&order1_, &order2_}) {
    const double value = product(*rule, p, q);
    out.evaluations += static_cast<long long>(rule->start[p + 1] - rule->start[p]) * (rule->start[q + 1] - rule->start[q]);
    out.value = value;
    out.error = std::abs(value - lower);
    if (met()) {
      found = true;
      return out;
    }
    lower = value;
  }
  return out;
}

}  // namespace radnet::geometry
