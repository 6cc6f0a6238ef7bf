#include "geometry/irradiance/sky_region.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

namespace radnet::geometry {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;
// A ball is taken whole once it subtends at most this sine of the cone's half-angle
// (14.5°): closer ones are opened, their children's cones are narrower. (30° left the
// 19,202-node satellite's kernel 27.9 M rays, 14.5° 21.9 M, 7.2° 17.2 M for a descent as
// long as the rays it saved.)
constexpr double kWholeBallSine = 0.25;
// Balls a node's descent may visit before it gives up on a sector (a tilted face's
// coplanar cells have boxes that stick out of its plane and are opened to the triangle).
constexpr int kMostVisits = 20000;
// Rounding margins: the cones' half-angles widened, the sector's radii moved outward.
constexpr double kAngleMargin = 1e-9, kRadiusMargin = 1e-12;

// The extents of one cone in the node's frame: θ (as sin²), φ (centre ± half; half ≥ π:
// every azimuth) and the box of its directions' (x, y) = (ω·t0, ω·t1).
struct ConeExtent {
  double r0_squared, r1_squared, phi_centre, phi_half;
  std::array<double, 4> box;  // x0, x1, y0, y1
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
  // ω·e over the cap spans cos of the angles from e in [β − α, β + α] (clipped to [0, π]).
  const auto extent = [&](const Vec3& e, double& from, double& to) {
    const double beta = std::acos(std::clamp(axis.dot(e), -1.0, 1.0));
    from = std::max(-1.0, std::cos(std::min(M_PI, beta + alpha)) - kRadiusMargin);
    to = std::min(1.0, std::cos(std::max(0.0, beta - alpha)) + kRadiusMargin);
  };
  extent(frame.t0, out.box[0], out.box[1]);
  extent(frame.t1, out.box[2], out.box[3]);
  return true;
}

using Box = std::array<double, 4>;
double boxArea(const Box& b) { return (b[1] - b[0]) * (b[3] - b[2]); }

Box boundingBox(const std::vector<Box>& boxes, size_t begin, size_t end) {
  Box b{HUGE_VAL, -HUGE_VAL, HUGE_VAL, -HUGE_VAL};
  for (size_t k = begin; k < end; ++k)
    b = {std::min(b[0], boxes[k][0]), std::max(b[1], boxes[k][1]), std::min(b[2], boxes[k][2]), std::max(b[3], boxes[k][3])};
  return b;
}

// The cones' boxes as at most 2^depth disjoint rectangles: split where the boxes separate
// along x or y (a gap between the first k by their lower edge and the rest), at the split
// whose two bounding boxes are smallest, while that saves a tenth of the area.
void disjointBoxes(std::vector<Box> boxes, int depth, std::vector<Box>& out) {
  const Box whole = boundingBox(boxes, 0, boxes.size());
  double best = 0.9 * boxArea(whole);
  int best_axis = -1;
  size_t best_k = 0;
  for (int axis = 0; axis < 2 && depth > 0; ++axis) {
    std::sort(boxes.begin(), boxes.end(), [axis](const Box& a, const Box& b) { return a[2 * axis] < b[2 * axis]; });
    double reach = -HUGE_VAL;
    for (size_t k = 0; k + 1 < boxes.size(); ++k) {
      reach = std::max(reach, boxes[k][2 * axis + 1]);
      if (reach >= boxes[k + 1][2 * axis]) continue;
      const double area = boxArea(boundingBox(boxes, 0, k + 1)) + boxArea(boundingBox(boxes, k + 1, boxes.size()));
      if (area < best) best = area, best_axis = axis, best_k = k + 1;
    }
  }
  if (best_axis < 0) {
    out.push_back(whole);
    return;
  }
  std::sort(boxes.begin(), boxes.end(), [best_axis](const Box& a, const Box& b) { return a[2 * best_axis] < b[2 * best_axis]; });
  disjointBoxes(std::vector<Box>(boxes.begin(), boxes.begin() + static_cast<std::ptrdiff_t>(best_k)), depth - 1, out);
  disjointBoxes(std::vector<Box>(boxes.begin() + static_cast<std::ptrdiff_t>(best_k), boxes.end()), depth - 1, out);
}

// The sector's azimuths: the arc covering every cone's.
void coveringArc(const std::vector<ConeExtent>& cones, SkyRegion& region) {
  std::vector<std::pair<double, double>> centre_half;
  for (const ConeExtent& c : cones) centre_half.emplace_back(c.phi_centre, c.phi_half);
  std::tie(region.phi0, region.phi_span) = geometry::coveringArc(centre_half);
}

}  // namespace

std::pair<double, double> coveringArc(const std::vector<std::pair<double, double>>& centre_half) {
  const std::pair<double, double> circle{0.0, kTwoPi};
  if (centre_half.empty()) return circle;
  std::vector<std::pair<double, double>> arcs;  // [start, end] within [0, 2π]
  for (const auto& [centre, half] : centre_half) {
    if (half >= M_PI) return circle;
    const double start = std::fmod(std::fmod(centre - half, kTwoPi) + kTwoPi, kTwoPi), end = start + 2.0 * half;
    if (end <= kTwoPi) {
      arcs.emplace_back(start, end);
    } else {  // split at 2π, so that the sweep sees what it covers at the start too
      arcs.emplace_back(start, kTwoPi);
      arcs.emplace_back(0.0, end - kTwoPi);
    }
  }
  std::sort(arcs.begin(), arcs.end());
  double reach = arcs.front().second, gap = 0.0, gap_end = arcs.front().first;
  for (size_t k = 1; k < arcs.size(); ++k) {
    if (arcs[k].first - reach > gap) gap = arcs[k].first - reach, gap_end = arcs[k].first;
    reach = std::max(reach, arcs[k].second);
  }
  if (arcs.front().first + kTwoPi - reach > gap) gap = arcs.front().first + kTwoPi - reach, gap_end = arcs.front().first;
  if (gap <= 0.0) return circle;
  return {gap_end, kTwoPi - gap};
}

double SkyRegion::share() const {
  if (whole) return 1.0;
  if (box_count == 0) return phi_span / kTwoPi * (r1_squared - r0_squared);
  double area = 0.0;
  for (int k = 0; k < box_count; ++k) area += boxArea(boxes[static_cast<size_t>(k)]);
  return area / M_PI;
}

bool SkyRegion::direction(double u2, double u3, Vec3& d) const {
  if (box_count == 0) {
    const double r2 = r0_squared + u2 * (r1_squared - r0_squared), r = std::sqrt(r2);
    const double phi = phi0 + u3 * phi_span;
    d = r * std::cos(phi) * t0 + r * std::sin(phi) * t1 + std::sqrt(std::max(0.0, 1.0 - r2)) * n;
    return true;
  }
  // u2 picks the rectangle by its share of the area, then, rescaled, the x within it.
  double total = 0.0;
  for (int k = 0; k < box_count; ++k) total += boxArea(boxes[static_cast<size_t>(k)]);
  double from = 0.0;
  int k = 0;
  for (; k + 1 < box_count; ++k) {
    const double to = from + boxArea(boxes[static_cast<size_t>(k)]) / total;
    if (u2 < to) break;
    from = to;
  }
  const Box& b = boxes[static_cast<size_t>(k)];
  const double width = boxArea(b) / total, s = width > 0 ? std::clamp((u2 - from) / width, 0.0, 1.0) : 0.5;
  const double x = b[0] + s * (b[1] - b[0]), y = b[2] + u3 * (b[3] - b[2]), r2 = x * x + y * y;
  if (r2 >= 1.0) return false;
  d = x * t0 + y * t1 + std::sqrt(1.0 - r2) * n;
  return true;
}

bool SkyRegion::contains(const Vec3& d) const {
  if (whole) return true;
  if (box_count > 0) {
    const double x = d.dot(t0), y = d.dot(t1);
    for (int k = 0; k < box_count; ++k) {
      const Box& b = boxes[static_cast<size_t>(k)];
      if (x >= b[0] && x <= b[1] && y >= b[2] && y <= b[3]) return true;
    }
    return false;
  }
  const double z = d.dot(n), r2 = 1.0 - z * z;
  if (r2 < r0_squared || r2 > r1_squared) return false;
  const double phi = std::atan2(d.dot(t1), d.dot(t0));
  return std::fmod(std::fmod(phi - phi0, kTwoPi) + kTwoPi, kTwoPi) <= phi_span;
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

bool BlockerSpheres::flatNode(int node_index, FlatNode& out) const {
  const Node& node = scene_.nodes()[static_cast<size_t>(node_index)];
  if (node.faces.empty() || balls_.empty()) return false;
  const Vec3 n = node.side * scene_.faces()[static_cast<size_t>(node.faces.front())].normal;
  if (!n.allFinite() || std::abs(n.norm() - 1.0) > 1e-9) return false;  // no usable normal
  // Flat: one normal, one plane (to a quarter of the rays' offset).
  double plane_lo = HUGE_VAL, plane_hi = -HUGE_VAL;
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = Vec3::Constant(-HUGE_VAL);
  for (const int f : node.faces) {
    const Face& face = scene_.faces()[static_cast<size_t>(f)];
    if ((node.side * face.normal - n).norm() > 1e-12) return false;
    for (const Vec3& v : face.v)
      plane_lo = std::min(plane_lo, n.dot(v)), plane_hi = std::max(plane_hi, n.dot(v)), lo = lo.cwiseMin(v),
      hi = hi.cwiseMax(v);
  }
  if (plane_hi - plane_lo > 0.25 * offset_m_) return false;
  out.n = n, out.centre = 0.5 * (lo + hi);
  // A triangle wholly at or below this height lies below every ray's origin (its plane
  // plus the offset, less rounding) and a ray leaving upward never meets it.
  out.below = plane_hi + 0.25 * offset_m_;
  out.radius = 0.0;
  for (const int f : node.faces)
    for (const Vec3& v : scene_.faces()[static_cast<size_t>(f)].v) out.radius = std::max(out.radius, (v - out.centre).norm());
  out.radius += 2.0 * offset_m_;
  return true;
}

bool BlockerSpheres::cones(const FlatNode& node, std::vector<std::pair<Vec3, double>>& out) const {
  const Vec3& n = node.n;
  std::vector<int> stack{0};
  int visits = 0;
  while (!stack.empty()) {
    const Ball& b = balls_[static_cast<size_t>(stack.back())];
    stack.pop_back();
    if (++visits > kMostVisits) return false;
    const bool leaf = b.left < 0;
    double top = -HUGE_VAL;  // the highest point of the ball's triangle (leaf) or box
    if (leaf)
      for (const Vec3& v : scene_.faces()[static_cast<size_t>(-1 - b.left)].v) top = std::max(top, n.dot(v));
    else
      top = n.dot(Vec3(n.x() > 0 ? b.hi.x() : b.lo.x(), n.y() > 0 ? b.hi.y() : b.lo.y(), n.z() > 0 ? b.hi.z() : b.lo.z()));
    if (top <= node.below) continue;
    const Vec3 toward = b.centre - node.centre;
    const double distance = toward.norm(), reach = b.radius + node.radius;
    if (reach >= distance && leaf) return false;  // a blocker touching the node: any direction
    if (reach >= distance || (!leaf && reach > kWholeBallSine * distance)) {
      stack.push_back(b.left), stack.push_back(b.right);
      continue;
    }
    out.emplace_back(toward / distance, std::asin(reach / distance));
  }
  return true;
}

std::array<SkyRegion, 2> BlockerSpheres::candidates(int node_index) const {
  std::array<SkyRegion, 2> both;  // whole unless found
  FlatNode node;
  std::vector<std::pair<Vec3, double>> axes;
  if (!flatNode(node_index, node) || !cones(node, axes)) return both;
  SkyRegion frame;
  frame.n = node.n, frame.t0 = node.n.unitOrthogonal(), frame.t1 = node.n.cross(frame.t0);
  std::vector<ConeExtent> extents;
  for (const auto& [axis, half_angle] : axes) {
    ConeExtent cone{};
    if (coneExtent(axis, half_angle, frame, cone)) extents.push_back(cone);
  }
  if (extents.empty()) return both;  // nothing in front (the kernel's own test finds it too)
  frame.whole = false;
  frame.r0_squared = 1.0, frame.r1_squared = 0.0;
  for (const ConeExtent& c : extents)
    frame.r0_squared = std::min(frame.r0_squared, c.r0_squared), frame.r1_squared = std::max(frame.r1_squared, c.r1_squared);
  coveringArc(extents, frame);
  std::vector<Box> boxes, disjoint;
  for (const ConeExtent& c : extents) boxes.push_back(c.box);
  disjointBoxes(std::move(boxes), 3, disjoint);
  SkyRegion boxed = frame;
  boxed.box_count = static_cast<int>(disjoint.size());
  for (size_t k = 0; k < disjoint.size(); ++k) boxed.boxes[k] = disjoint[k];
  return {frame, boxed};
}

SkyRegion BlockerSpheres::regionOf(int node_index, double max_share) const {
  const std::array<SkyRegion, 2> both = candidates(node_index);
  const SkyRegion& best = both[1].share() < both[0].share() ? both[1] : both[0];
  const double share = best.share();
  return share > 0.0 && share <= max_share ? best : SkyRegion{};  // (NaN: whole)
}

}  // namespace radnet::geometry
