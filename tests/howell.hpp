#pragma once
// Closed-form view factors from Howell's catalogue (A Catalog of Radiation Heat Transfer
// Configuration Factors): the independent truth of the view-factor tests and benchmarks.
#include <cmath>

namespace radnet::howell {

/// C-11: directly opposed parallel rectangles a × b at distance c.
inline double parallelRectangles(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x1 = 1 + x * x, y1 = 1 + y * y;
  return 2.0 / (M_PI * x * y) *
         (std::log(std::sqrt(x1 * y1 / (1 + x * x + y * y))) + x * std::sqrt(y1) * std::atan(x / std::sqrt(y1)) +
          y * std::sqrt(x1) * std::atan(y / std::sqrt(x1)) - x * std::atan(x) - y * std::atan(y));
}

/// C-14: perpendicular rectangles with a common edge of length l, widths w (from) and h (to).
inline double perpendicularRectangles(double l, double w, double h) {
  const double H = h / l, W = w / l;
  const double a = (1 + W * W) * (1 + H * H) / (1 + W * W + H * H);
  const double b = W * W * (1 + W * W + H * H) / ((1 + W * W) * (W * W + H * H));
  const double c = H * H * (1 + H * H + W * W) / ((1 + H * H) * (H * H + W * W));
  return 1.0 / (M_PI * W) *
         (W * std::atan(1 / W) + H * std::atan(1 / H) -
          std::sqrt(H * H + W * W) * std::atan(1 / std::sqrt(H * H + W * W)) +
          0.25 * std::log(a * std::pow(b, W * W) * std::pow(c, H * H)));
}

/// C-93 (Howell's catalogue): from the inside of the outer of two coaxial cylinders of one
/// length l to the outside of the inner one, radii r1 (inner) < r2 (outer).
inline double outerToInnerCylinder(double r1, double r2, double l) {
  const double R = r2 / r1, L = l / r1, A = L * L + R * R - 1, B = L * L - R * R + 1;
  const double pi = 3.14159265358979323846;
  const double f21 = 1 / R - 1 / (pi * R) *
                                 (std::acos(B / A) - 1 / (2 * L) *
                                                         (std::sqrt((A + 2) * (A + 2) - 4 * R * R) * std::acos(B / (R * A)) +
                                                          B * std::asin(1 / R) - pi * A / 2));
  return f21;
}

/// C-40: coaxial parallel discs, radii r1 (from) and r2 at distance h.
inline double coaxialDiscs(double r1, double r2, double h) {
  const double R1 = r1 / h, R2 = r2 / h, x = 1 + (1 + R2 * R2) / (R1 * R1);
  return 0.5 * (x - std::sqrt(x * x - 4 * (R2 / R1) * (R2 / R1)));
}

}  // namespace radnet::howell
