#include "simulate/recorder.h"

#include <iterator>
#include <numbers>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/pose.h"
#include "model/device.h"
#include "core/units.h"

namespace sscs {

namespace {
}  // namespace

TrajectoryRecorder::TrajectoryRecorder(const Workcell& wc, const GeometryModel& geometry, const PhysicsWorld& world,
                                       std::vector<int> devices)
    : wc_(wc), geometry_(geometry), world_(world), devices_(std::move(devices)), device_csv_(devices_.size()) {}

void TrajectoryRecorder::record(double t) {
  for (size_t k = 0; k < devices_.size(); ++k) {
    const int d = devices_[k];
    const Device& m = *geometry_.objects[d].device;
    if (device_csv_[k].empty()) {  // the header with the first row (a run stopped before any row writes none)
      std::vector<std::string> columns = {"t"};
      for (int j = 0; j < m.dof(); ++j) columns.push_back(m.joint(j).name);
      for (const char* c : {"tool_x", "tool_y", "tool_z", "tool_roll", "tool_pitch", "tool_yaw"}) columns.emplace_back(c);
      device_csv_[k] = fmt::format("{}\n", fmt::join(columns, ","));
    }
    Eigen::VectorXd q = world_.joints(d);
    auto row = std::back_inserter(device_csv_[k]);  // (formatted in place: a run's rows are most of its log)
    fmt::format_to(row, "{:.4f}", t);
    for (int j = 0; j < m.dof(); ++j) fmt::format_to(row, ",{:.6f}", m.joint(j).type == JointType::Revolute ? q[j] * kDegPerRad : q[j]);
    Eigen::Isometry3d X = world_.part_pose(d, m.tool_part) * m.X_part_tool;
    Eigen::Vector3d rpy = rotation_to_rpy(X.linear()) * kDegPerRad;
    fmt::format_to(row, ",{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f}\n", X.translation().x(), X.translation().y(), X.translation().z(),
                   rpy.x(), rpy.y(), rpy.z());
  }
  for (size_t o = 0; o < wc_.objects.size(); ++o) {
    if (!world_.dynamic(static_cast<int>(o))) continue;
    Eigen::Isometry3d X = world_.pose(static_cast<int>(o));
    Eigen::Vector3d rpy = rotation_to_rpy(X.linear()) * kDegPerRad;
    fmt::format_to(std::back_inserter(objects_csv_), "{:.4f},{},{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f}\n", t, wc_.objects[o].name,
                   X.translation().x(), X.translation().y(), X.translation().z(), rpy.x(), rpy.y(), rpy.z());
  }
}

std::vector<std::pair<std::string, std::string>> TrajectoryRecorder::files() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (size_t k = 0; k < devices_.size(); ++k)
    out.emplace_back(fmt::format("trajectories/{}.csv", wc_.objects[devices_[k]].name), device_csv_[k]);
  out.emplace_back("objects.csv", fmt::format("t,object,x,y,z,roll,pitch,yaw\n{}", objects_csv_));
  return out;
}

}  // namespace sscs
