#include "geometry/scene/primitives.hpp"

#include "solver/units.hpp"

#include <cmath>
#include <sstream>
#include <tuple>

namespace radnet::geometry {
namespace {

void requireCount(int n, const char* what) {
  if (n < 1 || n > 100000) throw GeometryError(std::string(what) + ": subdivisions must be in [1, 100000]");
}

// A surface of more triangles than this is a typo or beyond what the ray caster and the
// output are sized for (≈ 3 GB of mesh and AABB tree at 2e7 triangles).
constexpr double kMaxTrianglesPerSurface = 2e7;

void requireBudget(double a, double b, const char* what) {
  if (2.0 * a * b > kMaxTrianglesPerSurface) {
    std::ostringstream s;
    s << what << ": subdivisions " << a << " × " << b << " make " << 2.0 * a * b << " triangles; at most "
      << kMaxTrianglesPerSurface << " per surface";
    throw GeometryError(s.str());
  }
}

void requirePositive(double x, const char* what) {
  if (!(std::isfinite(x) && x > 0)) {
    std::ostringstream s;
    s << what << " is " << x << "; expected a finite value > 0";
    throw GeometryError(s.str());
  }
}

Vec3 unit(const Vec3& v, const char* what) {
  const double n = v.norm();
  if (!(std::isfinite(n) && n > 0)) throw GeometryError(std::string(what) + " must be a non-zero finite vector");
  return v / n;
}

// Orthonormal (e0, e1) spanning the plane normal to `axis`, e0 along the reference if given.
std::pair<Vec3, Vec3> planeFrame(const Vec3& axis, const std::optional<Vec3>& reference) {
  Vec3 e0;
  if (reference) {
    e0 = *reference - reference->dot(axis) * axis;
    if (e0.norm() < 1e-9 * reference->norm()) throw GeometryError("reference direction is parallel to the axis");
  } else {
    e0 = std::abs(axis.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    e0 -= e0.dot(axis) * axis;
  }
  e0.normalize();
  return {e0, axis.cross(e0)};
}

double sweepRadians(const Sweep& s) {
  const double span = units::degToRad(s.end_deg - s.start_deg);
  if (!(std::isfinite(span) && span > 0 && span <= 2 * M_PI + 1e-12))
    throw GeometryError("angle range must satisfy start < end ≤ start + 360°");
  return span;
}

bool fullTurn(const Sweep& s) { return (s.end_deg - s.start_deg) >= 360.0 - 1e-9; }

// The angular layout shared by discs, cones and spheres: an orthonormal frame normal to
// the axis, the swept range, and the number of segments (a closed turn needs at least 3).
struct AngularFrame {
  Vec3 axis, e0, e1;
  double start, span;
  bool wrap;
  int segments;
  Vec3 radial(double phi) const { return std::cos(phi) * e0 + std::sin(phi) * e1; }
};

AngularFrame angularFrame(const Vec3& axis_in, const Sweep& sweep, int angular, const char* what) {
  AngularFrame f;
  f.axis = unit(axis_in, what);
  std::tie(f.e0, f.e1) = planeFrame(f.axis, sweep.reference);
  f.span = sweepRadians(sweep);
  f.start = units::degToRad(sweep.start_deg);
  f.wrap = fullTurn(sweep);
  f.segments = std::max(angular, f.wrap ? 3 : 1);
  return f;
}

// Adds a (rows+1) × (cols+1) vertex grid, returning the index of vertex (0, 0); cells become two triangles.
template <class F>
void grid(TriangleSoup& soup, int rows, int cols, bool wrap_cols, F&& point) {
  const int base = static_cast<int>(soup.vertices.size());
  const int ncol = wrap_cols ? cols : cols + 1;
  for (int i = 0; i <= rows; ++i)
    for (int j = 0; j < ncol; ++j) soup.vertices.push_back(point(i, j));
  auto id = [&](int i, int j) { return base + i * ncol + (wrap_cols ? j % cols : j); };
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      soup.triangles.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
      soup.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
    }
}

// Scales each vertex's distance from the axis line (through `center` along `axis`; for a
// disc or sphere, from `center` itself) so that the facetted area matches `exact`.
void preserveArea(TriangleSoup& soup, const Vec3& center, const Vec3& axis, bool radial_only, double exact) {
  const std::vector<Vec3> original = soup.vertices;
  soup.nominal = original;
  auto apply = [&](double s) {
    for (size_t k = 0; k < original.size(); ++k) {
      const Vec3 d = original[k] - center;
      const Vec3 along = d.dot(axis) * axis;
      soup.vertices[k] = radial_only ? Vec3(center + along + s * (d - along)) : Vec3(center + s * d);
    }
    return soupArea(soup);
  };
  // Newton on ln A(s) = ln exact (A grows monotonically with s); the derivative by a
  // central difference, since a cone's area is not a power of its radial scale.
  double s = 1.0;
  for (int iter = 0; iter < 30; ++iter) {
    const double a = apply(s);
    if (std::abs(a / exact - 1.0) < 1e-15) return;
    const double h = 1e-6 * s;
    const double slope = (std::log(apply(s + h)) - std::log(apply(s - h))) / (std::log(s + h) - std::log(s - h));
    s *= std::exp((std::log(exact) - std::log(a)) / std::max(slope, 1e-3));
  }
  apply(s);
}

// Removes the triangles of a grid that collapse to zero area (a row of vertices at an apex
// or pole), relative to the primitive's size.
void dropCollapsed(TriangleSoup& soup, double size) {
  std::vector<std::array<int, 3>> kept;
  for (const auto& tri : soup.triangles) {
    const Vec3 c = (soup.vertices[tri[1]] - soup.vertices[tri[0]]).cross(soup.vertices[tri[2]] - soup.vertices[tri[0]]);
    if (c.norm() > 1e-14 * size * size) kept.push_back(tri);
  }
  soup.triangles = std::move(kept);
}

}  // namespace

double soupArea(const TriangleSoup& soup) {
  double a = 0.0;
  for (const auto& t : soup.triangles)
    a += 0.5 * (soup.vertices[t[1]] - soup.vertices[t[0]]).cross(soup.vertices[t[2]] - soup.vertices[t[0]]).norm();
  return a;
}

TriangleSoup rectangle(const Vec3& origin, const Vec3& u, const Vec3& v, int nu, int nv) {
  requireCount(nu, "rectangle");
  requireCount(nv, "rectangle");
  requireBudget(nu, nv, "rectangle");
  if (!(u.cross(v).norm() > 0)) throw GeometryError("rectangle: u and v must be non-zero and not parallel");
  TriangleSoup soup;
  grid(soup, nv, nu, false, [&](int i, int j) { return Vec3(origin + (double(j) / nu) * u + (double(i) / nv) * v); });
  return soup;
}

TriangleSoup quadrilateral(const std::array<Vec3, 4>& p, int nu, int nv) {
  requireCount(nu, "quadrilateral");
  requireCount(nv, "quadrilateral");
  requireBudget(nu, nv, "quadrilateral");
  const Vec3 n = (p[2] - p[0]).cross(p[3] - p[1]);
  const double scale = std::max((p[2] - p[0]).norm(), (p[3] - p[1]).norm());
  if (!(n.norm() > 0)) throw GeometryError("quadrilateral: corners are degenerate");
  const Vec3 nn = n.normalized();
  for (int k = 1; k < 4; ++k)
    if (std::abs((p[k] - p[0]).dot(nn)) > 1e-9 * scale) throw GeometryError("quadrilateral: corners are not coplanar");
  for (int k = 0; k < 4; ++k) {
    const Vec3 e0 = p[(k + 1) % 4] - p[k], e1 = p[(k + 2) % 4] - p[(k + 1) % 4];
    if (e0.cross(e1).dot(nn) <= 0) throw GeometryError("quadrilateral: corners must form a convex polygon in order");
  }
  TriangleSoup soup;
  grid(soup, nv, nu, false, [&](int i, int j) {
    const double s = double(j) / nu, t = double(i) / nv;
    return Vec3((1 - s) * (1 - t) * p[0] + s * (1 - t) * p[1] + s * t * p[2] + (1 - s) * t * p[3]);
  });
  return soup;
}

TriangleSoup triangle(const Vec3& a, const Vec3& b, const Vec3& c, int n) {
  requireCount(n, "triangle");
  requireBudget(n, n, "triangle");
  if (!((b - a).cross(c - a).norm() > 0)) throw GeometryError("triangle: corners are collinear");
  TriangleSoup soup;
  // Row i has i + 1 vertices: a + (i/n)(b − a) + (j/n)(c − b).
  std::vector<int> row_start;
  for (int i = 0; i <= n; ++i) {
    row_start.push_back(static_cast<int>(soup.vertices.size()));
    for (int j = 0; j <= i; ++j) soup.vertices.push_back(a + (double(i) / n) * (b - a) + (double(j) / n) * (c - b));
  }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j <= i; ++j) {
      const int v0 = row_start[i] + j, v1 = row_start[i + 1] + j, v2 = row_start[i + 1] + j + 1;
      soup.triangles.push_back({v0, v1, v2});
      if (j < i) soup.triangles.push_back({v0, v2, row_start[i] + j + 1});
    }
  return soup;
}

TriangleSoup disc(const Vec3& center, const Vec3& normal, double radius, double inner_radius, const Sweep& sweep,
                  int radial, int angular) {
  requireCount(radial, "disc");
  requireCount(angular, "disc");
  requireBudget(radial, angular, "disc");
  requirePositive(radius, "disc radius");
  if (!(std::isfinite(inner_radius) && inner_radius >= 0 && inner_radius < radius))
    throw GeometryError("disc: inner_radius must be in [0, radius)");
  const AngularFrame fr = angularFrame(normal, sweep, angular, "disc normal");
  const Vec3& axis = fr.axis;
  const double span = fr.span, start = fr.start;
  const bool wrap = fr.wrap;
  const int segments = fr.segments;
  auto at = [&](double r, double phi) { return Vec3(center + r * fr.radial(phi)); };
  TriangleSoup soup;
  const int rings = radial;
  if (inner_radius > 0) {
    grid(soup, rings, segments, wrap, [&](int i, int j) {
      return at(inner_radius + (radius - inner_radius) * i / rings, start + span * j / segments);
    });
  } else {
    // Centre fan, then rings of quads; the grid's row 0 is the first ring.
    soup.vertices.push_back(center);
    grid(soup, rings - 1, segments, wrap,
         [&](int i, int j) { return at(radius * (i + 1) / rings, start + span * j / segments); });
  }
  // The grid runs outward in r and counter-clockwise in φ, which faces −normal: flip it.
  for (auto& tri : soup.triangles) std::swap(tri[1], tri[2]);
  if (inner_radius == 0)
    for (int j = 0; j < segments; ++j) soup.triangles.push_back({0, 1 + j, 1 + (wrap ? (j + 1) % segments : j + 1)});
  preserveArea(soup, center, axis, false, 0.5 * span * (radius * radius - inner_radius * inner_radius));
  return soup;
}

TriangleSoup cone(const Vec3& base_center, const Vec3& axis_vec, double base_radius, double top_radius,
                  const Sweep& sweep, int axial, int angular) {
  requireCount(axial, "cone");
  requireCount(angular, "cone");
  requireBudget(axial, angular, "cone");
  if (!(std::isfinite(base_radius) && base_radius >= 0 && std::isfinite(top_radius) && top_radius >= 0 &&
        base_radius + top_radius > 0))
    throw GeometryError("cone: radii must be finite, >= 0 and not both zero");
  const double height = axis_vec.norm();
  const AngularFrame fr = angularFrame(axis_vec, sweep, angular, "cone axis");
  const Vec3& axis = fr.axis;
  const double span = fr.span, start = fr.start;
  const bool wrap = fr.wrap;
  const int segments = fr.segments;
  TriangleSoup soup;
  // Counter-clockwise in φ about the axis with rows going up the axis gives outward normals.
  grid(soup, axial, segments, wrap, [&](int i, int j) {
    const double t = double(i) / axial, phi = start + span * j / segments;
    const double r = base_radius + (top_radius - base_radius) * t;
    return Vec3(base_center + t * height * axis + r * fr.radial(phi));
  });
  dropCollapsed(soup, height);  // the row at an apex (zero radius) collapses
  const double slant = std::hypot(height, base_radius - top_radius);
  preserveArea(soup, base_center, axis, true, 0.5 * span * (base_radius + top_radius) * slant);
  soup.shape = {CurvedShape::Kind::Cone, base_center, axis, (top_radius - base_radius) / height};
  return soup;
}

TriangleSoup cylinder(const Vec3& base_center, const Vec3& axis, double radius, const Sweep& sweep, int axial,
                      int angular) {
  requirePositive(radius, "cylinder radius");
  return cone(base_center, axis, radius, radius, sweep, axial, angular);
}

TriangleSoup sphere(const Vec3& center, double radius, const Vec3& axis_in, double theta_min_deg, double theta_max_deg,
                    const Sweep& sweep, int polar, int azimuthal) {
  requireCount(polar, "sphere");
  requireCount(azimuthal, "sphere");
  requireBudget(polar, azimuthal, "sphere");
  requirePositive(radius, "sphere radius");
  if (!(theta_min_deg >= 0 && theta_max_deg <= 180 && theta_min_deg < theta_max_deg))
    throw GeometryError("sphere: polar range must satisfy 0 <= theta_min < theta_max <= 180");
  const AngularFrame fr = angularFrame(axis_in, sweep, azimuthal, "sphere axis");
  const Vec3& axis = fr.axis;
  const double span = fr.span, start = fr.start;
  const bool wrap = fr.wrap;
  const int segments = fr.segments;
  const double t0 = units::degToRad(theta_min_deg), t1 = units::degToRad(theta_max_deg);
  TriangleSoup soup;
  // Rows from θ_max down to θ_min so that (φ, row) runs counter-clockwise seen from outside.
  grid(soup, polar, segments, wrap, [&](int i, int j) {
    const double theta = t1 - (t1 - t0) * i / polar, phi = start + span * j / segments;
    return Vec3(center + radius * (std::cos(theta) * axis + std::sin(theta) * fr.radial(phi)));
  });
  dropCollapsed(soup, radius);  // the rows at the poles collapse
  preserveArea(soup, center, axis, false, span * radius * radius * (std::cos(t0) - std::cos(t1)));
  soup.shape = {CurvedShape::Kind::Sphere, center, axis, 0.0};
  return soup;
}

std::array<TriangleSoup, 6> boxFaces(const Vec3& o, const Vec3& size, int n) {
  for (int k = 0; k < 3; ++k) requirePositive(size[k], "box size");
  const Vec3 X(size.x(), 0, 0), Y(0, size.y(), 0), Z(0, 0, size.z());
  return {rectangle(o + X, Y, Z, n, n), rectangle(o, Z, Y, n, n),     rectangle(o + Y, Z, X, n, n),
          rectangle(o, X, Z, n, n),     rectangle(o + Z, X, Y, n, n), rectangle(o, Y, X, n, n)};
}

}  // namespace radnet::geometry
