#include "geometry/contour_view_factors.hpp"

#include <array>
#include <chrono>
#include <cmath>
#include <vector>

namespace radnet::geometry {
namespace {

// Dunavant (1985) degree-5 rule on a triangle: barycentric points and weights (sum 1).
struct QuadPoint {
  double l0, l1, l2, w;
};
const std::array<QuadPoint, 7> kRule = {{
    {1.0 / 3, 1.0 / 3, 1.0 / 3, 0.225},
    {0.059715871789770, 0.470142064105115, 0.470142064105115, 0.132394152788506},
    {0.470142064105115, 0.059715871789770, 0.470142064105115, 0.132394152788506},
    {0.470142064105115, 0.470142064105115, 0.059715871789770, 0.132394152788506},
    {0.797426985353087, 0.101286507323456, 0.101286507323456, 0.125939180544827},
    {0.101286507323456, 0.797426985353087, 0.101286507323456, 0.125939180544827},
    {0.101286507323456, 0.101286507323456, 0.797426985353087, 0.125939180544827},
}};

// Shadow-ray targets on a receiving triangle (barycentric), centroid first.
const std::array<std::array<double, 3>, 4> kTargets = {{{1.0 / 3, 1.0 / 3, 1.0 / 3},
                                                        {2.0 / 3, 1.0 / 6, 1.0 / 6},
                                                        {1.0 / 6, 2.0 / 3, 1.0 / 6},
                                                        {1.0 / 6, 1.0 / 6, 2.0 / 3}}};

struct Tri {
  Vec3 a, b, c;
};

class Integrator {
 public:
  Integrator(const RayCaster& caster, int from, const ContourOptions& opt)
      : caster_(caster), scene_(caster.scene()), opt_(opt), n_(static_cast<int>(scene_.nodes().size())) {
    side_ = scene_.nodes()[static_cast<size_t>(from)].side;
  }

  // ∫ over the emitter triangle of the point-to-node form factors (vector over receivers), m².
  void integrate(int face, Eigen::VectorXd& sum, Eigen::VectorXd& err) {
    const Face& f = scene_.faces()[static_cast<size_t>(face)];
    face_ = face;
    normal_ = side_ * f.normal;
    const Tri t{f.v[0], f.v[1], f.v[2]};
    Eigen::VectorXd coarse = rule(t);
    adapt(t, coarse, opt_.tolerance * f.area_m2, 0, sum, err);
  }
  long long evaluations = 0;

 private:
  Eigen::VectorXd rule(const Tri& t) {
    const double area = 0.5 * (t.b - t.a).cross(t.c - t.a).norm();
    Eigen::VectorXd acc = Eigen::VectorXd::Zero(n_);
    for (const auto& q : kRule) acc += (q.w * area) * pointFactors(q.l0 * t.a + q.l1 * t.b + q.l2 * t.c);
    return acc;
  }

  void adapt(const Tri& t, const Eigen::VectorXd& coarse, double tol, int depth, Eigen::VectorXd& sum,
             Eigen::VectorXd& err) {
    const Vec3 ab = 0.5 * (t.a + t.b), bc = 0.5 * (t.b + t.c), ca = 0.5 * (t.c + t.a);
    const std::array<Tri, 4> kids = {{{t.a, ab, ca}, {ab, t.b, bc}, {ca, bc, t.c}, {ab, bc, ca}}};
    std::array<Eigen::VectorXd, 4> parts;
    Eigen::VectorXd fine = Eigen::VectorXd::Zero(n_);
    for (int k = 0; k < 4; ++k) {
      parts[static_cast<size_t>(k)] = rule(kids[static_cast<size_t>(k)]);
      fine += parts[static_cast<size_t>(k)];
    }
    const double diff = (fine - coarse).cwiseAbs().maxCoeff();
    if (diff <= tol || depth >= opt_.max_depth) {
      sum += fine;
      err += (fine - coarse).cwiseAbs();
      return;
    }
    for (int k = 0; k < 4; ++k)
      adapt(kids[static_cast<size_t>(k)], parts[static_cast<size_t>(k)], 0.25 * tol, depth + 1, sum, err);
  }

  // Form factors from the point to every receiving node (dimensionless), occlusion sampled.
  Eigen::VectorXd pointFactors(const Vec3& p) {
    ++evaluations;
    Eigen::VectorXd out = Eigen::VectorXd::Zero(n_);
    const Vec3 origin = caster_.offsetOrigin(p, normal_);
    const auto& faces = scene_.faces();
    for (size_t g = 0; g < faces.size(); ++g) {
      if (static_cast<int>(g) == face_) continue;
      const Face& r = faces[g];
      // Which side of r does p see? That side's node receives.
      const bool sees_front = (p - r.v[0]).dot(r.normal) > 0;
      const int node = sees_front ? r.front_node : r.back_node;
      if (node < 0) continue;
      const double f = pointToTriangle(p, normal_, r.v[0], r.v[1], r.v[2], sees_front ? r.normal : Vec3(-r.normal));
      if (f <= 0) continue;
      out[node] += f * visibility(origin, static_cast<int>(g));
    }
    return out;
  }

  double visibility(const Vec3& origin, int target) {
    if (opt_.visibility_rays <= 0) return 1.0;
    const Face& r = scene_.faces()[static_cast<size_t>(target)];
    const int rays = std::min<int>(opt_.visibility_rays, static_cast<int>(kTargets.size()));
    int clear = 0;
    for (int k = 0; k < rays; ++k) {
      const auto& b = kTargets[static_cast<size_t>(k)];
      const Vec3 q = b[0] * r.v[0] + b[1] * r.v[1] + b[2] * r.v[2];
      const Vec3 d = q - origin;
      const double dist = d.norm();
      if (d.dot(normal_) <= 0) continue;  // behind the emitter's tangent plane
      const Hit hit = caster_.firstHit(origin, d / dist, face_);
      if (hit.face == target || hit.face < 0 || hit.distance >= dist * (1 - 1e-9)) ++clear;
    }
    return double(clear) / rays;
  }

  const RayCaster& caster_;
  const Scene& scene_;
  const ContourOptions& opt_;
  int n_;
  double side_ = 1.0;
  int face_ = -1;
  Vec3 normal_;
};

}  // namespace

double pointToTriangle(const Vec3& p, const Vec3& n, const Vec3& a, const Vec3& b, const Vec3& c,
                       const Vec3& receiver_normal) {
  if ((p - a).dot(receiver_normal) <= 0) return 0.0;  // the point is behind the receiving side
  // Clip the triangle to the half-space n·(x − p) ≥ 0 (Sutherland–Hodgman, one plane).
  const std::array<Vec3, 3> in = {a, b, c};
  std::array<Vec3, 4> poly;
  int m = 0;
  for (int k = 0; k < 3; ++k) {
    const Vec3& u = in[static_cast<size_t>(k)];
    const Vec3& v = in[static_cast<size_t>((k + 1) % 3)];
    const double du = n.dot(u - p), dv = n.dot(v - p);
    if (du >= 0) poly[static_cast<size_t>(m++)] = u;
    if ((du >= 0) != (dv >= 0)) poly[static_cast<size_t>(m++)] = u + (du / (du - dv)) * (v - u);
  }
  if (m < 3) return 0.0;
  double sum = 0.0;
  for (int k = 0; k < m; ++k) {
    const Vec3 r0 = poly[static_cast<size_t>(k)] - p, r1 = poly[static_cast<size_t>((k + 1) % m)] - p;
    const Vec3 cr = r0.cross(r1);
    const double crn = cr.norm();
    if (crn <= 1e-300) continue;  // edge seen end-on: no contribution
    const double gamma = std::atan2(crn, r0.dot(r1));
    sum += gamma * n.dot(cr) / crn;
  }
  return std::abs(sum) / (2.0 * M_PI);
}

ContourResult contourViewFactors(const RayCaster& caster, const ContourOptions& opt) {
  const Scene& scene = caster.scene();
  const int n = static_cast<int>(scene.nodes().size());
  const auto t0 = std::chrono::steady_clock::now();
  ContourResult res;
  res.view_factors = Eigen::MatrixXd::Zero(n, n);
  res.error_estimate = Eigen::MatrixXd::Zero(n, n);
  long long evaluations = 0;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : evaluations)
#endif
  for (int i = 0; i < n; ++i) {
    Integrator integ(caster, i, opt);
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(n), err = Eigen::VectorXd::Zero(n);
    const Node& node = scene.nodes()[static_cast<size_t>(i)];
    for (int face : node.faces) integ.integrate(face, sum, err);
    res.view_factors.row(i) = sum.transpose() / node.area_m2;
    res.error_estimate.row(i) = err.transpose() / node.area_m2;
    evaluations += integ.evaluations;
  }
  res.point_evaluations = evaluations;
  res.space = (Eigen::VectorXd::Ones(n) - res.view_factors.rowwise().sum()).cwiseMax(0.0);
  res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

}  // namespace radnet::geometry
