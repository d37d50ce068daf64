#pragma once
/// Camera keyframes compiled: units to SI, object names to indices, checked. A vault's named
/// cameras are compiled with the vault (Workcell::cameras); a scenario's and a camera file's when
/// a command reads them. render/camera_path.h interpolates them.
#include <vector>

#include <Eigen/Geometry>

#include "core/diagnostics.h"
#include "load/spec.h"

namespace sscs {

struct Workcell;

struct CameraKey {
  double t = 0;              ///< s
  bool orbit = false;
  Eigen::Vector3d eye = Eigen::Vector3d::Zero(), target = Eigen::Vector3d::Zero();  ///< fixed keys
  int orbit_object = -1;     ///< orbit around an object's origin (where it is at that moment) ...
  Eigen::Vector3d orbit_point = Eigen::Vector3d::Zero();  ///< ... or around a point
  double radius = 0, azimuth = 0, elevation = 0;         ///< m, rad, rad
  double fov = 45;           ///< deg
};

/// Compiles the keys (units, object names, fov in (1, 179) deg, times not decreasing). Errors go
/// to `diag` with their marks.
std::vector<CameraKey> compile_camera_keys(const std::vector<CameraKeySpec>& keys, const Workcell& wc, Diagnostics& diag);

}  // namespace sscs
