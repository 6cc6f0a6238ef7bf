#pragma once
// `articulation:` parts of the geometry that turn about a drive's axis during an orbit (a
// Sun-tracking wing, a steered antenna; docs/case-files.md, "Moving parts"). Angles are
// right-handed about axis.direction through axis.point, 0 the geometry as written.
#include "cases/config/yaml_document.hpp"
#include "orbits/sweep.hpp"

#include <Eigen/Dense>

#include <string>
#include <vector>

namespace radnet::cases {

struct Drive {
  std::string name;
  std::vector<std::string> parts;  ///< geometry item names, as written
  std::vector<int> surfaces;       ///< their scene surfaces
  std::vector<int> nodes;          ///< the scene nodes on them (each wholly on the part)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      ///< on the axis, body frame, m
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX(); ///< unit, body frame
  enum class Track { Sun, Fixed, Table } track = Track::Fixed;
  double angle_deg = 0.0;  ///< Fixed
  std::vector<double> table_t_s, table_deg;  ///< Table: (s since the orbit case's epoch, deg)
  /// Angles are rounded to multiples of this, deg (the drive moves in steps); 0: not binned
  /// (a fixed angle).
  double step_deg = 0.0;
  /// Sun tracking: the parts' area-weighted front normal at angle 0, body frame, unit.
  Eigen::Vector3d front_normal = Eigen::Vector3d::UnitZ();
  /// The angle at each position, deg, in (−180, 180] (binned to step_deg).
  std::vector<double> angles(const std::vector<orbits::SweepPosition>& positions) const;
};

/// Drives that turn during the orbit (tracking or tabulated); fixed-angle drives are applied to
/// the scene as it is read and are not kept here but in `fixed_drives` (name, angle).
struct Articulation {
  std::vector<Drive> drives;
  std::vector<std::pair<std::string, double>> fixed_drives;  ///< (name, deg), already turned in the scene
  bool empty() const { return drives.empty() && fixed_drives.empty(); }
  /// Every drive's name: the moving ones, then the fixed ones.
  std::vector<std::string> names() const;
  /// The moving drives' angles at each position (positions × drives, deg, binned): a
  /// configuration per distinct row (Articulated::configure; counted ahead by the memory
  /// estimate, work_estimate.cpp).
  Eigen::MatrixXd movingAngles(const std::vector<orbits::SweepPosition>& positions) const;
};

/// The step a drive defaults to under `solver.accuracy`: the largest divisor of 360° whose
/// half keeps a tracked front's cosine loss 1 − cos(step/2) within a tenth of the accuracy
/// (5° at the default 0.01), deg.
double defaultDriveStep(double accuracy);

struct GeometryCase;
/// Parses `articulation:` (after the scene, the optics, the solver block and the cases);
/// turns fixed-angle drives' parts in the scene. @throws InputError with file:line:column
void parseArticulation(const YamlDocument& doc, GeometryCase& c);

}  // namespace radnet::cases
