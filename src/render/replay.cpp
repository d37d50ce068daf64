#include "render/replay.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "core/pose.h"
#include "model/device.h"
#include "core/units.h"

namespace sscs {

namespace {


std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  for (std::string cell; std::getline(ss, cell, ',');) out.push_back(cell);
  return out;
}

/// Cell `k` of a CSV row as a finite number, else why not (with the file and line).
Expected<double> number_at(const std::vector<std::string>& cells, size_t k, const std::string& path, int line) {
  if (k >= cells.size()) return Unexpected{fmt::format("{}:{}: a row of {} cells, expected at least {}", path, line, cells.size(), k + 1)};
  const std::string& c = cells[k];
  double v = 0;
  const char* first = c.data() + (c.starts_with('+') ? 1 : 0);
  auto [end, ec] = std::from_chars(first, c.data() + c.size(), v);
  if (ec != std::errc() || end != c.data() + c.size() || !std::isfinite(v))
    return Unexpected{fmt::format("{}:{}: column {} is '{}', expected a finite number (is the log corrupt?)", path, line, k + 1, c)};
  return v;
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

std::string replay_target_refusal(const std::string& out, bool force) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(out, ec))) return "";
  if (!fs::is_directory(fs::symlink_status(out, ec)))
    return fmt::format("--out '{}' is a file; a replay writes a folder, and never replaces anything else: choose another --out", out);
  if (fs::is_empty(out, ec)) return "";
  bool replay = fs::exists(fs::path(out) / "frames" / "index.csv", ec);
  for (const fs::directory_entry& e : fs::directory_iterator(out, ec))
    replay = replay && (e.path().filename() == "frames" || e.path().filename() == "contact_sheet.png");
  if (!replay)
    return fmt::format("--out '{}' exists and is not an earlier replay; it is never replaced, even with --force: choose another "
                       "--out", out);
  if (!force) return fmt::format("--out '{}' holds an earlier replay; pass --force to replace it, or choose another --out", out);
  return "";
}

Expected<RecordedRun> RecordedRun::read(const std::string& dir, const Workcell& wc, const GeometryModel& geometry,
                                        const std::vector<int>& driven) {
  RecordedRun run;
  run.geometry_ = &geometry;
  run.dir_ = dir;
  for (size_t o = 0; o < wc.objects.size(); ++o) {
    const auto& device = geometry.objects[o].device;
    if (!device) continue;
    std::string path = fmt::format("{}/trajectories/{}.csv", dir, wc.objects[o].name);
    std::ifstream in(path);
    if (!in) {
      if (std::find(driven.begin(), driven.end(), static_cast<int>(o)) == driven.end()) continue;  // not moved: no log
      return Unexpected{fmt::format("{}: missing, though the run moved {} (is the run folder complete?)", path, wc.objects[o].name)};
    }
    std::string line;
    std::getline(in, line);
    std::vector<std::string> head = split(line);
    if (head.empty() || head[0] != "t" || head.size() != static_cast<size_t>(1 + device->dof() + 6))
      return Unexpected{fmt::format("{}:1: the header is '{}', expected t, the {} joints of {} and the tool's x,y,z,roll,pitch,yaw",
                                    path, line, device->dof(), wc.objects[o].name)};
    std::vector<int> column(device->dof(), -1);
    for (int j = 0; j < device->dof(); ++j)
      for (size_t c = 0; c < head.size(); ++c)
        if (head[c] == device->joint(j).name) column[j] = static_cast<int>(c);
    if (std::count(column.begin(), column.end(), -1))
      return Unexpected{fmt::format("{}: its columns do not match the joints of {}", path, wc.objects[o].name)};
    Series& s = run.devices_[static_cast<int>(o)];
    for (int row = 2; std::getline(in, line); ++row) {
      std::vector<std::string> cells = split(line);
      if (cells.size() != head.size())
        return Unexpected{fmt::format("{}:{}: a row of {} cells, expected {} as in the header (is the log corrupt?)", path, row,
                                      cells.size(), head.size())};
      Eigen::VectorXd q(device->dof());
      for (int j = 0; j < device->dof(); ++j) {
        Expected<double> v = number_at(cells, column[j], path, row);
        if (!v) return Unexpected{v.error()};
        q[j] = *v * (device->joint(j).type == JointType::Revolute ? kRadPerDeg : 1.0);
      }
      Expected<double> t = number_at(cells, 0, path, row);
      if (!t) return Unexpected{t.error()};
      if (!s.t.empty() && *t < s.t.back()) return Unexpected{fmt::format("{}:{}: time {} comes before {} (is the log corrupt?)", path, row, *t, s.t.back())};
      s.t.push_back(*t);
      s.values.push_back(q);
    }
    if (!s.t.empty()) run.duration_ = std::max(run.duration_, s.t.back());
  }
  std::ifstream in(dir + "/objects.csv");
  if (!in) return Unexpected{fmt::format("{}: not a run folder (no objects.csv)", dir)};
  const std::string path = dir + "/objects.csv";
  std::string line;
  std::getline(in, line);
  if (line != "t,object,x,y,z,roll,pitch,yaw")
    return Unexpected{fmt::format("{}:1: the header is '{}', expected t,object,x,y,z,roll,pitch,yaw", path, line)};
  for (int row = 2; std::getline(in, line); ++row) {
    std::vector<std::string> c = split(line);
    if (c.size() != 8) return Unexpected{fmt::format("{}:{}: a row of {} cells, expected 8 (t,object,x,y,z,roll,pitch,yaw)", path, row, c.size())};
    int o = wc.find_object(c[1]);
    if (o < 0) return Unexpected{fmt::format("{}:{}: object '{}' is not in the run's vault", path, row, c[1])};
    double x[8];
    for (size_t k : {0, 2, 3, 4, 5, 6, 7}) {
      Expected<double> v = number_at(c, k, path, row);
      if (!v) return Unexpected{v.error()};
      x[k] = *v;
    }
    Eigen::Quaterniond q(rpy_to_rotation(x[5] * kRadPerDeg, x[6] * kRadPerDeg, x[7] * kRadPerDeg));
    Eigen::VectorXd v(7);
    v << x[2], x[3], x[4], q.w(), q.x(), q.y(), q.z();
    Series& s = run.objects_[o];
    if (!s.t.empty() && x[0] < s.t.back()) return Unexpected{fmt::format("{}:{}: time {} comes before {} (is the log corrupt?)", path, row, x[0], s.t.back())};
    s.t.push_back(x[0]);
    s.values.push_back(v);
    run.duration_ = std::max(run.duration_, s.t.back());
  }
  return run;
}

Expected<std::vector<double>> RecordedRun::frame_times(double fps) const {
  std::vector<double> times;
  const std::string path = dir_ + "/frames/index.csv";
  std::ifstream index(path);
  if (!index) {
    for (int n = 0; n <= static_cast<int>(duration_ * fps + 1e-9); ++n) times.push_back(static_cast<double>(n) / fps);
    return times;
  }
  std::string line;
  std::getline(index, line);
  if (line != "frame,t,file") return Unexpected{fmt::format("{}:1: the header is '{}', expected frame,t,file", path, line)};
  for (int row = 2; std::getline(index, line); ++row) {
    const std::vector<std::string> cells = split(line);
    const int n = row - 2;
    if (cells.size() != 3 || cells[0] != std::to_string(n) || cells[2] != fmt::format("frame_{:06d}.png", n))
      return Unexpected{fmt::format("{}:{}: '{}', expected frame {} as '{},<t>,frame_{:06d}.png' (is the index corrupt?)", path, row,
                                    line, n, n, n)};
    Expected<double> t = number_at(cells, 1, path, row);
    if (!t) return Unexpected{t.error()};
    if (!times.empty() && *t < times.back())
      return Unexpected{fmt::format("{}:{}: time {} comes before {} (is the index corrupt?)", path, row, *t, times.back())};
    if (*t < 0 || *t > duration_ + 1)  // (a frame may follow the last logged row by up to a log interval)
      return Unexpected{fmt::format("{}:{}: time {} lies outside the run (0 to {} s; is the index corrupt?)", path, row, *t,
                                    duration_)};
    times.push_back(*t);
  }
  if (times.empty()) return Unexpected{fmt::format("{}: lists no frame (is the index corrupt?)", path)};
  return times;
}

std::vector<double> RecordedRun::log_times() const {
  std::vector<double> all{0.0};
  for (const auto* series : {&devices_, &objects_})
    for (const auto& [o, s] : *series) all.insert(all.end(), s.t.begin(), s.t.end());
  std::sort(all.begin(), all.end());
  std::vector<double> out;
  for (double t : all)
    if (out.empty() || static_cast<float>(t) > static_cast<float>(out.back())) out.push_back(t);
  return out;
}

std::vector<int> RecordedRun::logged_objects() const {
  std::vector<int> out;
  for (const auto* series : {&devices_, &objects_})
    for (const auto& [o, s] : *series) out.push_back(o);
  for (const auto& [o, t] : arrivals_) out.push_back(o);  // they appear
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
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
  for (const auto& [o, arrived] : arrivals_)
    if (t < arrived - 1e-9) {
      if (pose.hidden.empty()) pose.hidden.assign(pose.X_world_object.size(), 0);
      pose.hidden[o] = 1;
      pose.X_world_object[o] = absent_pose(o);
    }
  return pose;
}

}  // namespace sscs
