#include "orbits/attitude.hpp"

#include "solver/units.hpp"

#include <cmath>

namespace radnet::orbits {
namespace {

Eigen::Vector3d targetEci(Target target, const Eigen::Vector3d& fixed, const Orbit& orbit, const OrbitState& st,
                          const Eigen::Vector3d& sun, double t) {
  switch (target) {
    case Target::Sun: return sun;
    case Target::Nadir: return -st.position_eci_m.normalized();
    case Target::Zenith: return st.position_eci_m.normalized();
    case Target::Velocity: return st.velocity_eci_m_s.normalized();
    case Target::OrbitNormal: return orbit.normal(t);
    case Target::Inertial: return fixed.normalized();
  }
  return fixed;
}

}  // namespace

Eigen::Matrix3d triad(const Eigen::Vector3d& a1, const Eigen::Vector3d& a2, const Eigen::Vector3d& b1,
                      const Eigen::Vector3d& b2) {
  // Orthonormal frames (a1, a1×a2, a1×(a1×a2)) in body and the same of the targets in ECI;
  // bodyFromEci maps the ECI frame onto the body frame.
  const Eigen::Vector3d ua = a1.normalized(), ub = b1.normalized();
  const Eigen::Vector3d va = ua.cross(a2), vb = ub.cross(b2);
  if (va.norm() < 1e-9 || vb.norm() < 1e-9)
    throw OrbitError("attitude: the primary and secondary directions are parallel; the roll is undefined");
  Eigen::Matrix3d body, eci;
  body << ua, va.normalized(), ua.cross(va.normalized());
  eci << ub, vb.normalized(), ub.cross(vb.normalized());
  return body * eci.transpose();
}

Eigen::Matrix3d bodyFromEci(const AttitudeSpec& spec, const Orbit& orbit, const OrbitState& st,
                            const Eigen::Vector3d& sun, double t) {
  using Mode = AttitudeSpec::Mode;
  switch (spec.mode) {
    case Mode::Nadir: {
      const Eigen::Vector3d z = -st.position_eci_m.normalized();
      const Eigen::Vector3d x = (st.velocity_eci_m_s - st.velocity_eci_m_s.dot(z) * z).normalized();
      const Eigen::Vector3d y = z.cross(x);
      Eigen::Matrix3d eciFromBody;
      eciFromBody << x, y, z;
      return eciFromBody.transpose();
    }
    case Mode::Sun: return triad(Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), sun, orbit.normal(t));
    case Mode::Inertial: return spec.body_from_eci.normalized().toRotationMatrix();
    case Mode::Spin: {
      // The body turns by θ about its axis: v_body(t) = R(−θ) v_body(0).
      const double theta = units::degToRad(spec.spin_rate_deg_s) * t;
      return Eigen::AngleAxisd(-theta, spec.spin_axis_body.normalized()).toRotationMatrix() *
             spec.body_from_eci.normalized().toRotationMatrix();
    }
    case Mode::Pointing: {
      const PointingSpec& p = spec.pointing;
      return triad(p.primary_body, p.secondary_body, targetEci(p.primary, p.primary_eci, orbit, st, sun, t),
                   targetEci(p.secondary, p.secondary_eci, orbit, st, sun, t));
    }
  }
  return Eigen::Matrix3d::Identity();
}

bool earthFixedInBody(const AttitudeSpec& spec) {
  if (spec.mode == AttitudeSpec::Mode::Nadir) return true;
  if (spec.mode != AttitudeSpec::Mode::Pointing) return false;
  const PointingSpec& p = spec.pointing;
  const bool earthish1 = p.primary == Target::Nadir || p.primary == Target::Zenith;
  const bool orbital2 = p.secondary == Target::Velocity || p.secondary == Target::OrbitNormal;
  return earthish1 && orbital2;
}

}  // namespace radnet::orbits
