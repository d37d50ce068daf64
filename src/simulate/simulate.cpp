#include "simulate/simulate.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/pose.h"
#include "kinematics/device.h"
#include "simulate/world.h"

namespace fs = std::filesystem;

namespace sscs {

const char* run_status_name(RunStatus s) {
  switch (s) {
    case RunStatus::Ok: return "ok";
    case RunStatus::Violations: return "violations";
    case RunStatus::Failed: return "failed";
  }
  return "?";
}

namespace {

constexpr double kTrackingTolerance = 0.005;  // m: the tool may lag its plan by this much
constexpr double kLimitTolerance = 1e-3;      // rad or m past a joint limit before it is an event
constexpr double kSettleLimit = 5.0;          // s after the last step for released objects to settle
constexpr double kApart = 0.1;                // s apart before a touching pair counts as a new contact
constexpr double kRad = 180 / 3.14159265358979323846;

/// Rounded for logs: 9 decimals (nanometres, nanoradians) keep files stable and readable.
double r9(double x) { return std::round(x * 1e9) / 1e9; }

class Run {
 public:
  Run(const Workcell& wc, const GeometryModel& geometry, const Plan& plan, const RunOptions& options)
      : wc_(wc), geometry_(geometry), plan_(plan), options_(options),
        world_(wc, geometry, PhysicsOptions{plan.settings.timestep, plan.settings.gravity}) {}

  RunSummary run() {
    const SimSettings& s = plan_.settings;
    const double dt = s.timestep;
    for (const Track& t : plan_.tracks) {
      world_.add_device(t.object, t.q_start);
      devices_.push_back({t.object, &t, t.q_start, tool_now(t.object), 0, Eigen::VectorXd::Zero(t.q_start.size()), {}, false});
    }
    const long every = std::max(1L, std::lround(1.0 / (s.rate * dt)));
    std::vector<char> started(plan_.steps.size(), 0), ended(plan_.steps.size(), 0);
    double settle_until = -1;
    long k = 0;
    for (;; ++k) {
      const double t = k * dt;
      // Step boundaries, grasps and releases due now.
      for (size_t i = 0; i < plan_.steps.size(); ++i) {
        const PlannedStep& ps = plan_.steps[i];
        if (!started[i] && ps.start <= t + dt / 2) {
          started[i] = 1;
          step_event(t, "step_start", ps);
          if (ps.kind == "grasp") {
            world_.grasp(ps.device, ps.object);
            event(t, "grasp", {{"device", wc_.objects[ps.device].name}, {"object", wc_.objects[ps.object].name}});
          } else if (ps.kind == "release" && world_.held(ps.device) >= 0) {
            int o = world_.held(ps.device);
            world_.release(ps.device);
            released_[o] = false;
            event(t, "release", {{"device", wc_.objects[ps.device].name}, {"object", wc_.objects[o].name}});
          }
        }
        if (started[i] && !ended[i] && ps.end <= t + dt / 2) {
          ended[i] = 1;
          step_event(t, "step_end", ps);
        }
      }
      if (k % every == 0) record(t);
      if (plan_.failure && plan_.failure->t <= t + dt / 2) {
        const PlanFailure& f = *plan_.failure;
        nlohmann::ordered_json fields = {{"step", f.step}, {"device", wc_.objects[f.device].name}, {"message", f.message}};
        if (f.kind == "unreachable") fields["position_error"] = r9(f.position_error);
        event(t, f.kind, fields);
        failed_ = true;
        break;
      }
      if (t >= plan_.end - dt / 2) {
        if (settle_until < 0) settle_until = t + kSettleLimit;
        bool settled = true;
        for (const auto& [o, landed] : released_) settled = settled && world_.at_rest(o);
        if (settled || t >= settle_until) break;
      }
      if (t >= s.limit - dt / 2) {
        event(t, "time_limit", {{"limit", s.limit}});
        failed_ = true;
        break;
      }
      if (options_.progress && k % std::max(1L, std::lround(1.0 / dt)) == 0)
        std::cerr << fmt::format("simulate: t = {:.1f} s of {:.1f} s\n", t, plan_.end);
      for (const DeviceRun& dr : devices_) {
        Eigen::VectorXd q1 = dr.track->at(t + dt);
        world_.drive(dr.object, q1, (q1 - dr.track->at(t)) / dt);
      }
      world_.step();
      after_step(world_.time());
    }
    return finish(k * dt);
  }

  std::string write(const RunSummary& summary, std::string* error) {
    fs::path out(options_.out_dir);
    fs::path tmp = out.parent_path() / fmt::format(".{}.tmp-{}", out.filename().string(), ::getpid());
    std::error_code ec;
    fs::remove_all(tmp, ec);
    fs::create_directories(tmp / "trajectories", ec);
    if (ec) return *error = fmt::format("cannot create '{}': {}", tmp.string(), ec.message());
    auto put = [&](const fs::path& p, const std::string& text) {
      std::ofstream f(p, std::ios::binary);
      f << text;
      if (!f) *error = fmt::format("cannot write '{}'", p.string());
    };
    put(tmp / "summary.json", fmt::format("{}\n", summary_json(summary).dump(2)));
    std::string events;
    for (const auto& e : events_) events += fmt::format("{}\n", e.dump());
    put(tmp / "events.jsonl", events);
    for (const DeviceRun& dr : devices_) put(tmp / "trajectories" / fmt::format("{}.csv", wc_.objects[dr.object].name), dr.csv);
    put(tmp / "objects.csv", fmt::format("t,object,x,y,z,roll,pitch,yaw\n{}", objects_csv_));
    if (!error->empty()) return *error;
    if (fs::exists(out, ec)) fs::remove_all(out, ec);
    fs::rename(tmp, out, ec);
    if (ec) *error = fmt::format("cannot move the run into '{}': {}", out.string(), ec.message());
    return *error;
  }

 private:
  struct DeviceRun {
    int object;
    const Track* track;
    Eigen::VectorXd q_prev;
    Eigen::Vector3d tool_prev;
    double path = 0;
    Eigen::VectorXd travel;
    std::string csv;
    bool lagging = false;
  };

  Eigen::Vector3d tool_now(int d) const {
    const Device& m = *geometry_.objects[d].device;
    return (world_.part_pose(d, m.tool_part) * m.X_part_tool).translation();
  }

  std::string part_name(int o, int part) const {
    if (o < 0) return "floor";
    const ObjectGeometry& g = geometry_.objects[o];
    return part >= 0 && g.device ? fmt::format("{}.{}", wc_.objects[o].name, g.device->parts[part].name) : wc_.objects[o].name;
  }

  void event(double t, const std::string& kind, nlohmann::ordered_json fields = nlohmann::ordered_json::object()) {
    nlohmann::ordered_json e;
    e["t"] = r9(t);
    e["kind"] = kind;
    for (auto& [k, v] : fields.items()) e[k] = v;
    events_.push_back(std::move(e));
    counts_[kind]++;
  }

  void step_event(double t, const char* kind, const PlannedStep& ps) {
    nlohmann::ordered_json f = {{"step", ps.index}, {"action", ps.kind}};
    if (ps.device >= 0) f["device"] = wc_.objects[ps.device].name;
    event(t, kind, f);
  }

  /// The gripper touching the object it is about to grasp, or has just released, is not a
  /// collision: the tool's part (and the parts it carries) against the device's next grasp
  /// target or its last released object.
  bool gripper_meets_its_load(const PhysicsContact& c, double t) const {
    for (auto [dev, part, other] : {std::tuple{c.a, c.part_a, c.b}, std::tuple{c.b, c.part_b, c.a}}) {
      if (dev < 0 || part < 0 || other < 0 || !geometry_.objects[dev].device) continue;
      if (!geometry_.objects[dev].device->tool_parts()[part]) continue;
      int next = -1, last = -1;
      for (const PlannedStep& ps : plan_.steps) {
        if (ps.device != dev) continue;
        if (ps.kind == "grasp" && ps.start >= t - plan_.settings.timestep && next < 0) next = ps.object;
        if (ps.kind == "release" && ps.start <= t) last = ps.object;
      }
      if (other == next || other == last) return true;
    }
    return false;
  }

  bool held_anywhere(int o) const {
    for (const DeviceRun& dr : devices_)
      if (world_.held(dr.object) == o) return true;
    return false;
  }

  void after_step(double t) {
    // Contacts: a pair is one event until it has been apart for kApart (contacts flicker).
    for (const PhysicsContact& c : world_.contacts()) {
      auto key = std::make_tuple(c.a, c.part_a, c.b, c.part_b);
      auto last = last_contact_.find(key);
      bool ongoing = last != last_contact_.end() && t - last->second <= kApart;
      last_contact_[key] = t;
      if (ongoing) continue;
      if (gripper_meets_its_load(c, t)) continue;
      bool device_part = (c.a >= 0 && c.part_a >= 0) || (c.b >= 0 && c.part_b >= 0);
      bool carried = (c.a >= 0 && held_anywhere(c.a)) || (c.b >= 0 && held_anywhere(c.b));
      if (device_part || carried) {
        event(t, "collision", {{"a", part_name(c.a, c.part_a)}, {"b", part_name(c.b, c.part_b)},
                               {"point", {r9(c.point.x()), r9(c.point.y()), r9(c.point.z())}}, {"depth", r9(c.depth)}});
        continue;
      }
      for (int o : {c.a, c.b}) {
        auto it = released_.find(o);
        if (it != released_.end() && !it->second) {
          it->second = true;
          int other = o == c.a ? c.b : c.a;
          event(t, "landed", {{"object", wc_.objects[o].name}, {"on", part_name(other, -1)}});
        }
      }
    }
    for (auto& [o, landed] : released_)
      if (landed && world_.at_rest(o) && !rested_.count(o)) {
        rested_.insert(o);
        const Eigen::Vector3d p = world_.pose(o).translation();
        event(t, "at_rest", {{"object", wc_.objects[o].name}, {"position", {r9(p.x()), r9(p.y()), r9(p.z())}}});
      }
    for (DeviceRun& dr : devices_) {
      const Device& m = *geometry_.objects[dr.object].device;
      Eigen::VectorXd q = world_.joints(dr.object);
      dr.travel += (q - dr.q_prev).cwiseAbs();
      dr.q_prev = q;
      Eigen::Vector3d tool = tool_now(dr.object);
      dr.path += (tool - dr.tool_prev).norm();
      dr.tool_prev = tool;
      for (int j = 0; j < m.dof(); ++j) {
        const Joint& jt = m.joint(j);
        bool past = q[j] < jt.lower - kLimitTolerance || q[j] > jt.upper + kLimitTolerance;
        auto key = std::make_pair(dr.object, j);
        if (past && !over_limit_.count(key)) {
          over_limit_.insert(key);
          event(t, "joint_limit", {{"device", wc_.objects[dr.object].name}, {"joint", jt.name}, {"value", r9(q[j])}});
        } else if (!past) {
          over_limit_.erase(key);
        }
      }
      Eigen::Vector3d planned =
          (geometry_.objects[dr.object].X_world_object * m.tool_pose(dr.track->at(t))).translation();
      double lag = (tool - planned).norm();
      if (lag > kTrackingTolerance && !dr.lagging) {
        dr.lagging = true;
        event(t, "tracking_error", {{"device", wc_.objects[dr.object].name}, {"deviation", r9(lag)}});
      } else if (lag < kTrackingTolerance / 2) {
        dr.lagging = false;
      }
    }
  }

  void record(double t) {
    for (DeviceRun& dr : devices_) {
      const Device& m = *geometry_.objects[dr.object].device;
      if (dr.csv.empty()) {
        std::vector<std::string> columns = {"t"};
        for (int j = 0; j < m.dof(); ++j) columns.push_back(m.joint(j).name);
        for (const char* c : {"tool_x", "tool_y", "tool_z", "tool_roll", "tool_pitch", "tool_yaw"}) columns.emplace_back(c);
        dr.csv = fmt::format("{}\n", fmt::join(columns, ","));
      }
      Eigen::VectorXd q = world_.joints(dr.object);
      std::string row = fmt::format("{:.4f}", t);
      for (int j = 0; j < m.dof(); ++j)
        row += fmt::format(",{:.6f}", m.joint(j).type == JointType::Revolute ? q[j] * kRad : q[j]);
      Eigen::Isometry3d X = world_.part_pose(dr.object, m.tool_part) * m.X_part_tool;
      Eigen::Vector3d rpy = rotation_to_rpy(X.linear()) * kRad;
      row += fmt::format(",{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f}\n", X.translation().x(), X.translation().y(),
                         X.translation().z(), rpy.x(), rpy.y(), rpy.z());
      dr.csv += row;
    }
    for (size_t o = 0; o < wc_.objects.size(); ++o) {
      if (!world_.dynamic(static_cast<int>(o))) continue;
      Eigen::Isometry3d X = world_.pose(static_cast<int>(o));
      Eigen::Vector3d rpy = rotation_to_rpy(X.linear()) * kRad;
      objects_csv_ += fmt::format("{:.4f},{},{:.6f},{:.6f},{:.6f},{:.4f},{:.4f},{:.4f}\n", t, wc_.objects[o].name,
                                  X.translation().x(), X.translation().y(), X.translation().z(), rpy.x(), rpy.y(), rpy.z());
    }
  }

  RunSummary finish(double t_end) {
    RunSummary s;
    s.cycle_time = failed_ ? t_end : plan_.end;
    s.simulated = t_end;
    s.events = events_.size();
    s.collisions = counts_.count("collision") ? counts_.at("collision") : 0;
    bool violations = s.collisions > 0 || counts_.count("joint_limit") || counts_.count("tracking_error");
    s.status = failed_ ? RunStatus::Failed : violations ? RunStatus::Violations : RunStatus::Ok;
    return s;
  }

  nlohmann::ordered_json summary_json(const RunSummary& s) const {
    nlohmann::ordered_json j;
    j["sscs"] = 1;
    j["scenario"] = options_.scenario_name;
    j["vault"] = wc_.name;
    j["status"] = run_status_name(s.status);
    j["cycle_time"] = r9(s.cycle_time);
    j["simulated_time"] = r9(s.simulated);
    auto steps = nlohmann::ordered_json::array();
    for (const PlannedStep& ps : plan_.steps) {
      nlohmann::ordered_json st = {{"index", ps.index}, {"action", ps.kind}};
      st["device"] = ps.device >= 0 ? nlohmann::ordered_json(wc_.objects[ps.device].name) : nullptr;
      if (ps.object >= 0) st["object"] = wc_.objects[ps.object].name;
      st["start"] = r9(ps.start);
      st["end"] = r9(ps.end);
      steps.push_back(std::move(st));
    }
    j["steps"] = std::move(steps);
    nlohmann::ordered_json devices = nlohmann::ordered_json::object();
    for (const DeviceRun& dr : devices_) {
      const Device& m = *geometry_.objects[dr.object].device;
      nlohmann::ordered_json travel = nlohmann::ordered_json::object();
      for (int k = 0; k < m.dof(); ++k)
        travel[m.joint(k).name] = r9(m.joint(k).type == JointType::Revolute ? dr.travel[k] * kRad : dr.travel[k]);
      devices[wc_.objects[dr.object].name] = {{"joint_travel", travel}, {"joint_travel_units", "deg for revolute joints, m for prismatic"},
                                              {"tool_path_length", r9(dr.path)}};
    }
    j["devices"] = std::move(devices);
    nlohmann::ordered_json counts = nlohmann::ordered_json::object();
    for (const auto& [kind, n] : counts_) counts[kind] = n;
    j["events"] = std::move(counts);
    j["sscs_version"] = SSCS_VERSION;
    return j;
  }

  const Workcell& wc_;
  const GeometryModel& geometry_;
  const Plan& plan_;
  const RunOptions& options_;
  PhysicsWorld world_;
  std::vector<DeviceRun> devices_;
  std::vector<nlohmann::ordered_json> events_;
  std::map<std::string, size_t> counts_;
  std::map<std::tuple<int, int, int, int>, double> last_contact_;
  std::map<int, bool> released_;  // released objects: landed yet?
  std::set<int> rested_;
  std::set<std::pair<int, int>> over_limit_;
  std::string objects_csv_;
  bool failed_ = false;
};

}  // namespace

RunSummary run_simulation(const Workcell& wc, const GeometryModel& geometry, const Plan& plan, const RunOptions& options,
                          std::string* error) {
  Run run(wc, geometry, plan, options);
  RunSummary summary = run.run();
  if (!options.out_dir.empty()) run.write(summary, error);
  return summary;
}

}  // namespace sscs
