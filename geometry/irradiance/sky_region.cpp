#include "geometry/irradiance/sky_region.hpp"

#include <algorithm>
#include <cmath>

namespace radnet::geometry {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;
// A ball is taken whole once it subtends at most this sine of the cone's half-angle (30°):
// closer ones are opened, their children's cones are narrower.
constexpr double kWholeBallSine = 0.5;
// Balls a node's descent may visit before it gives up on a sector (a tilted face's
// coplanar cells have boxes that stick out of its plane and are opened to the triangle).
constexpr int kMostVisits = 20000;
// Rounding margins: the cones' half-angles widened, the sector's radii moved outward.
constexpr double kAngleMargin = 1e-9, kRadiusMargin = 1e-12;

// The extents of one cone in the node's frame: θ (as sin²) and φ (centre ± half; half ≥ π:
// every azimuth).
struct ConeExtent {
  double r0_squared, r1_squared, phi_centre, phi_half;
};

bool coneExtent(const Vec3& axis, double half_angle, const SkyRegion& frame, ConeExtent& out) {
  const double alpha = half_angle + kAngleMargin;
  const double theta = std::acos(std::clamp(axis.dot(frame.n), -1.0, 1.0));
  const double lo = std::max(0.0, theta - alpha), hi = std::min(M_PI / 2, theta + alpha);
  if (lo >= M_PI / 2) return false;  // wholly below the horizon: no ray goes there
  out.r0_squared = std::sin(lo) * std::sin(lo) * (1.0 - kRadiusMargin);
  out.r1_squared = std::min(1.0, std::sin(hi) * std::sin(hi) * (1.0 + kRadiusMargin));
  out.phi_centre = std::atan2(axis.dot(frame.t1), axis.dot(frame.t0));
  const double s = theta > alpha && theta + alpha < M_PI ? std::sin(alpha) / std::sin(theta) : 2.0;
  out.phi_half = s >= 1.0 ? M_PI : std::asin(s) + kAngleMargin;
  return true;
}

// The shortest arc covering every cone's azimuths: the complement of the largest gap
// between them (none: the whole circle).
void coveringArc(std::vector<ConeExtent>& cones, SkyRegion& region) {
  region.phi0 = 0.0, region.phi_span = kTwoPi;
  for (const ConeExtent& c : cones)
    if (c.phi_half >= M_PI) return;
  std::vector<std::pair<double, double>> arcs;  // [start, end), start in [0, 2π)
  for (const ConeExtent& c : cones) {
    const double start = std::fmod(std::fmod(c.phi_centre - c.phi_half, kTwoPi) + kTwoPi, kTwoPi);
    arcs.emplace_back(start, start + 2.0 * c.phi_half);
  }
  std::sort(arcs.begin(), arcs.end());
  double reach = arcs.front().second, gap = 0.0, gap_end = arcs.front().first;
  for (size_t k = 1; k < arcs.size(); ++k) {
    if (arcs[k].first - reach > gap) gap = arcs[k].first - reach, gap_end = arcs[k].first;
    reach = std::max(reach, arcs[k].second);
  }
  if (arcs.front().first + kTwoPi - reach > gap) gap = arcs.front().first + kTwoPi - reach, gap_end = arcs.front().first;
  if (gap <= 0.0) return;
  region.phi0 = gap_end, region.phi_span = kTwoPi - gap;
}

}  // namespace

double SkyRegion::share() const { return whole ? 1.0 : phi_span / kTwoPi * (r1_squared - r0_squared); }

Vec3 SkyRegion::direction(double u2, double u3) const {
  const double r2 = r0_squared + u2 * (r1_squared - r0_squared), r = std::sqrt(r2);
  const double phi = phi0 + u3 * phi_span;
  return r * std::cos(phi) * t0 + r * std::sin(phi) * t1 + std::sqrt(std::max(0.0, 1.0 - r2)) * n;
}

BlockerSpheres::BlockerSpheres(const Scene& scene, double origin_offset_m) : scene_(scene), offset_m_(origin_offset_m) {
  std::vector<int> faces(scene.faces().size());
  for (size_t f = 0; f < faces.size(); ++f) faces[f] = static_cast<int>(f);
  balls_.reserve(2 * faces.size());
  if (!faces.empty()) build(faces, 0, static_cast<int>(faces.size()));
}

// Top-down by the centroids' median along the widest axis; a ball per subtree, the smaller
// of its box's half-diagonal and its children's balls' reach.
int BlockerSpheres::build(std::vector<int>& faces, int begin, int end) {
  const int at = static_cast<int>(balls_.size());
  balls_.emplace_back();
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL), clo = lo, chi = hi;
  for (int k = begin; k < end; ++k) {
    const Face& f = scene_.faces()[static_cast<size_t>(faces[static_cast<size_t>(k)])];
    const Vec3 centroid = (f.v[0] + f.v[1] + f.v[2]) / 3.0;
    clo = clo.cwiseMin(centroid), chi = chi.cwiseMax(centroid);
    for (const Vec3& v : f.v) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  }
  Ball ball;
  ball.lo = lo, ball.hi = hi, ball.centre = 0.5 * (lo + hi), ball.radius = 0.5 * (hi - lo).norm();
  if (end - begin == 1) {
    const Face& f = scene_.faces()[static_cast<size_t>(faces[static_cast<size_t>(begin)])];
    ball.radius = 0.0;
    for (const Vec3& v : f.v) ball.radius = std::max(ball.radius, (v - ball.centre).norm());
    ball.left = -1 - faces[static_cast<size_t>(begin)];  // a leaf: −1 − its triangle
    balls_[static_cast<size_t>(at)] = ball;
    return at;
  }
  int axis = 0;
  (chi - clo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  const auto centroid = [&](int f) {
    const Face& face = scene_.faces()[static_cast<size_t>(f)];
    return face.v[0][axis] + face.v[1][axis] + face.v[2][axis];
  };
  std::nth_element(faces.begin() + begin, faces.begin() + mid, faces.begin() + end,
                   [&](int a, int b) { return centroid(a) < centroid(b); });
  const int left = build(faces, begin, mid), right = build(faces, mid, end);
  double reach = 0.0;
  for (const int child : {left, right})
    reach = std::max(reach, (balls_[static_cast<size_t>(child)].centre - ball.centre).norm() +
                                balls_[static_cast<size_t>(child)].radius);
  ball.radius = std::min(ball.radius, reach);
  ball.left = left, ball.right = right;
  balls_[static_cast<size_t>(at)] = ball;
  return at;
}

SkyRegion BlockerSpheres::regionOf(int node_index, double max_share) const {
  SkyRegion region;
  const Node& node = scene_.nodes()[static_cast<size_t>(node_index)];
  if (node.faces.empty() || balls_.empty()) return region;
  const Vec3 n = node.side * scene_.faces()[static_cast<size_t>(node.faces.front())].normal;
  // Flat: one normal, one plane (to a quarter of the rays' offset).
  double plane_lo = HUGE_VAL, plane_hi = -HUGE_VAL;
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (const int f : node.faces) {
    const Face& face = scene_.faces()[static_cast<size_t>(f)];
    if ((node.side * face.normal - n).norm() > 1e-12) return region;
    for (const Vec3& v : face.v)
      plane_lo = std::min(plane_lo, n.dot(v)), plane_hi = std::max(plane_hi, n.dot(v)), lo = lo.cwiseMin(v),
      hi = hi.cwiseMax(v);
  }
  if (plane_hi - plane_lo > 0.25 * offset_m_) return region;
  // A triangle wholly at or below this height lies below every ray's origin (its plane
  // plus the offset, less rounding) and a ray leaving upward never meets it.
  const double below = plane_hi + 0.25 * offset_m_;
  const Vec3 centre = 0.5 * (lo + hi);
  double node_radius = 0.0;
  for (const int f : node.faces)
    for (const Vec3& v : scene_.faces()[static_cast<size_t>(f)].v) node_radius = std::max(node_radius, (v - centre).norm());
  node_radius += 2.0 * offset_m_;
  SkyRegion frame;
  frame.n = n, frame.t0 = n.unitOrthogonal(), frame.t1 = n.cross(frame.t0);
  std::vector<ConeExtent> cones;
  std::vector<int> stack{0};
  int visits = 0;
  while (!stack.empty()) {
    const Ball& b = balls_[static_cast<size_t>(stack.back())];
    stack.pop_back();
    if (++visits > kMostVisits) return region;
    const bool leaf = b.left < 0;
    double top = 0.0;  // the highest point of the ball's triangles (leaf) or box
    if (leaf) {
      top = -HUGE_VAL;
      for (const Vec3& v : scene_.faces()[static_cast<size_t>(-1 - b.left)].v) top = std::max(top, n.dot(v));
    } else {
      top = n.dot(Vec3(n.x() > 0 ? b.hi.x() : b.lo.x(), n.y() > 0 ? b.hi.y() : b.lo.y(), n.z() > 0 ? b.hi.z() : b.lo.z()));
    }
    if (top <= below) continue;
    const Vec3 toward = b.centre - centre;
    const double distance = toward.norm(), reach = b.radius + node_radius;
    if (reach >= distance) {
      if (leaf) return region;  // a blocker touching the node: any direction
      stack.push_back(b.left), stack.push_back(b.right);
      continue;
    }
    if (!leaf && reach > kWholeBallSine * distance) {
      stack.push_back(b.left), stack.push_back(b.right);
      continue;
    }
    ConeExtent cone{};
    if (coneExtent(toward / distance, std::asin(reach / distance), frame, cone)) cones.push_back(cone);
  }
  if (cones.empty()) return region;  // nothing in front (the kernel's own test finds it too)
  frame.r0_squared = 1.0, frame.r1_squared = 0.0;
  for (const ConeExtent& c : cones)
    frame.r0_squared = std::min(frame.r0_squared, c.r0_squared), frame.r1_squared = std::max(frame.r1_squared, c.r1_squared);
  coveringArc(cones, frame);
  frame.whole = false;
  if (frame.share() > max_share) return region;
  return frame;
}

}  // namespace radnet::geometry
