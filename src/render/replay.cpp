#include "render/replay.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "core/pose.h"
#include "model/device.h"

namespace sscs {

namespace {

constexpr double kDeg = std::numbers::pi / 180;

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  return out;
}

/// The bracketing rows of t and the fraction between them.
std::tuple<size_t, size_t, double> bracket(const std::vector<double>& ts, double t) {
  if (t <= ts.front()) return {0, 0, 0.0};
  if (t >= ts.back()) return {ts.size() - 1, ts.size() - 1, 0.0};
  size_t b = static_cast<size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin());
  size_t a = b - 1;
  return {a, b, (t - ts[a]) / (ts[b] - ts[a])};
}

}  // namespace

std::optional<RecordedRun> RecordedRun::read(const std::string& dir, const Workcell& wc, const GeometryModel& geometry,
                                             std::string* error) {
  RecordedRun run;
  run.geometry_ = &geometry;
  for (size_t o = 0; o < wc.objects.size(); ++o) {
    const auto& device = geometry.objects[o].device;
    if (!device) continue;
    std::string path = fmt::format("{}/trajectories/{}.csv", dir, wc.objects[o].name);
    std::ifstream in(path);
    if (!in) continue;  // a device the scenario did not move
    std::string line;
    std::getline(in, line);
    std::vector<std::string> head = split(line);
    std::vector<int> column(device->dof(), -1);
    for (int j = 0; j < device->dof(); ++j)
      for (size_t c = 0; c < head.size(); ++c)
        if (head[c] == device->joint(j).name) column[j] = static_cast<int>(c);
    if (std::count(column.begin(), column.end(), -1)) {
      *error = fmt::format("{}: its columns do not match the joints of {}", path, wc.objects[o].name);
      return std::nullopt;
    }
    Series& s = run.devices_[static_cast<int>(o)];
    while (std::getline(in, line)) {
      std::vector<std::string> cells = split(line);
      Eigen::VectorXd q(device->dof());
      for (int j = 0; j < device->dof(); ++j)
        q[j] = std::stod(cells.at(column[j])) * (device->joint(j).type == JointType::Revolute ? kDeg : 1.0);
      s.t.push_back(std::stod(cells.at(0)));
      s.values.push_back(q);
    }
    if (!s.t.empty()) run.duration_ = std::max(run.duration_, s.t.back());
  }
  std::ifstream in(dir + "/objects.csv");
  if (!in) {
    *error = fmt::format("{}: not a run folder (no objects.csv)", dir);
    return std::nullopt;
  }
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> c = split(line);
    if (c.size() != 8) continue;
    int o = wc.find_object(c[1]);
    if (o < 0) {
      *error = fmt::format("{}/objects.csv: object '{}' is not in the run's vault", dir, c[1]);
      return std::nullopt;
    }
    Eigen::Quaterniond q(rpy_to_rotation(std::stod(c[5]) * kDeg, std::stod(c[6]) * kDeg, std::stod(c[7]) * kDeg));
    Eigen::VectorXd v(7);
    v << std::stod(c[2]), std::stod(c[3]), std::stod(c[4]), q.w(), q.x(), q.y(), q.z();
    Series& s = run.objects_[o];
    s.t.push_back(std::stod(c[0]));
    s.values.push_back(v);
    run.duration_ = std::max(run.duration_, s.t.back());
  }
  return run;
}

ScenePose RecordedRun::at(double t) const {
  ScenePose pose = ScenePose::of(*geometry_);
  for (const auto& [o, s] : devices_) {
    if (s.t.empty()) continue;
    auto [a, b, f] = bracket(s.t, t);
    Eigen::VectorXd q = s.values[a] + f * (s.values[b] - s.values[a]);
    pose.X_object_part[o] = geometry_->objects[o].device->part_poses(q);
  }
  for (const auto& [o, s] : objects_) {
    if (s.t.empty() || t < s.t.front() - 1e-9) continue;  // not moving yet: where it stood
    auto [a, b, f] = bracket(s.t, t);
    const Eigen::VectorXd &va = s.values[a], &vb = s.values[b];
    Eigen::Quaterniond qa(va[3], va[4], va[5], va[6]), qb(vb[3], vb[4], vb[5], vb[6]);
    Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
    X.linear() = qa.slerp(f, qb).toRotationMatrix();
    X.translation() = va.head<3>() + f * (vb.head<3>() - va.head<3>());
    pose.X_world_object[o] = X;
  }
  return pose;
}

}  // namespace sscs
