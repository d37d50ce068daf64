// Scenario files: `sscs: 1`, `scenario: NAME`, vault, set, sim, record, cameras, steps.
#include <filesystem>

#include <fmt/format.h>

#include "core/names.h"
#include "core/yaml_tree.h"
#include "load/campaign.h"
#include "load/load.h"
#include "load/reader.h"
#include "load/run_file.h"
#include "load/scenario.h"

#include "core/files.h"

namespace fs = std::filesystem;

namespace sscs {

using load::MapReader;

namespace {

// The action keys of a step: exactly one of these per step.
const std::vector<std::string> kActions(std::begin(kStepActionNames), std::end(kStepActionNames));

TargetSpec read_target(yaml::Node node, Diagnostics& diag) {
  TargetSpec t;
  t.mark = node.valid() ? node.mark() : SourceMark{};
  if (node.is_map()) {
    MapReader r(node, "move_to target pose", diag);
    t.pose = load::pose(r, diag);
    r.finish();
  } else {
    t.ref = load::scalar(node, "move_to target", diag);
  }
  return t;
}

}  // namespace

namespace load {

namespace {
void read_action(StepSpec& s, std::string_view kind, yaml::Node v, Diagnostics& diag, bool templated) {
  if (kind == "move_joints") {
    MoveJointsSpec m;
    if (v.is_scalar() && v.text() == "home") {
      m.home = true;
    } else if (v.is_map()) {
      MapReader j(v, "move_joints", diag);
      for (auto& [k, val] : j.rest()) {
        m.joints.emplace_back(load::name(k, "a joint", diag), load::scalar(val, "a joint value", diag));
        m.joint_marks.push_back(k.mark());
      }
      if (m.joints.empty()) load::expected(diag, v, "joint values {joint: value, ...} or home", "move_joints");
    } else {
      load::expected(diag, v, "joint values {joint: value, ...} or home", "move_joints");
    }
    s.action = std::move(m);
  } else if (kind == "move_to") {
    MoveToSpec m;
    MapReader r(v, "move_to", diag);
    if (r.ok()) {
      m.target = read_target(r.require("target"), diag);
      yaml::Node offset = r.take("offset");
      if (offset.valid()) {
        MapReader o(offset, "offset", diag);
        m.offset = load::pose(o, diag);
        o.finish();
      }
      r.finish();
    }
    s.action = std::move(m);
  } else if (kind == "grasp") {
    s.action = GraspSpec{load::scalar(v, "grasp", diag)};
  } else if (kind == "release") {
    ReleaseSpec rel;
    if (v.is_map()) {
      MapReader r(v, "release", diag);
      rel.object = load::scalar(r.take("object"), "release object", diag);
      r.finish();
    } else if (!v.is_null()) {
      rel.object = load::scalar(v, "release", diag);
    }
    s.action = std::move(rel);
  } else if (kind == "wait") {
    s.action = WaitSpec{load::scalar(v, "wait", diag)};
  } else {  // parallel
    ParallelSpec p;
    if (!v.is_sequence() || v.size() == 0) {
      load::expected(diag, v, "a non-empty sequence of steps", "parallel");
    } else {
      for (size_t i = 0; i < v.size(); ++i) {
        StepSpec inner = read_step(v.item(i), diag, templated);
        if (std::holds_alternative<ParallelSpec>(inner.action))
          diag.error(inner.mark, "a parallel group cannot hold another parallel group");
        p.steps.push_back(std::move(inner));
      }
    }
    s.action = std::move(p);
  }
}

}  // namespace

StepSpec read_step(yaml::Node node, Diagnostics& diag, bool templated) {
  StepSpec s;
  s.mark = node.mark();
  s.action = WaitSpec{};
  MapReader r(node, "step", diag);
  if (!r.ok()) return s;
  // Exactly one action key.
  std::vector<std::pair<std::string, yaml::Node>> actions;
  for (const std::string& k : kActions)
    if (yaml::Node v = r.take(k); v.valid()) actions.emplace_back(k, v);
  yaml::Node device = r.take("device");
  s.device = load::scalar(device, "step device", diag);
  s.speed = load::scalar(r.take("speed"), "speed", diag);
  yaml::Node path = r.take("path");
  if (actions.empty()) {
    // Name the unknown key the user probably meant as the action.
    std::string found;
    for (auto& [k, v] : r.rest()) found = found.empty() ? std::string(k.text()) : found;
    diag.error(s.mark, found.empty()
                           ? fmt::format("a step needs one action: {}", fmt::join(kActions, ", "))
                           : fmt::format("unknown step kind '{}'; expected one of {}{}", found, fmt::join(kActions, ", "),
                                         did_you_mean(found, kActions)));
    return s;
  }
  if (actions.size() > 1)
    diag.error(actions[1].second.mark(), fmt::format("a step has one action; this one has '{}' and '{}' (use parallel "
                                                      "to run steps together)", actions[0].first, actions[1].first));
  const auto& [kind, value] = actions[0];
  read_action(s, kind, value, diag, templated);
  bool needs_device = kind != "wait" && kind != "parallel";
  if (needs_device && !s.device.present && !templated) diag.error(s.mark, fmt::format("a {} step needs 'device'", kind));
  if (!needs_device && s.device.present) diag.error(s.device.mark, fmt::format("a {} step takes no 'device'", kind));
  if (s.speed.present && kind != "move_joints" && kind != "move_to")
    diag.error(s.speed.mark, fmt::format("'speed' applies to move_joints and move_to, not {}", kind));
  if (path.valid()) {
    auto* m = std::get_if<MoveToSpec>(&s.action);
    std::string word = load::text(path, "path", diag);
    if (!m) diag.error(path.mark(), "'path' applies to move_to steps");
    else if (word == "linear") m->linear = true;
    else if (word != "joint") load::expected(diag, path, "joint or linear", "path");
  }
  r.finish();
  return s;
}

std::vector<StepSpec> read_steps(yaml::Node steps, Diagnostics& diag, bool templated) {
  std::vector<StepSpec> out;
  if (steps.valid() && (!steps.is_sequence() || steps.size() == 0)) {
    load::expected(diag, steps, "a non-empty sequence of steps", "steps");
  } else if (steps.valid()) {
    for (size_t i = 0; i < steps.size() && !diag.full(); ++i) out.push_back(read_step(steps.item(i), diag, templated));
  }
  return out;
}

}  // namespace load

namespace {
std::vector<CameraKeySpec> read_cameras(yaml::Node cameras, Diagnostics& diag) {
  std::vector<CameraKeySpec> out;
  if (!cameras.valid()) return out;
  if (!cameras.is_sequence()) load::expected(diag, cameras, "a sequence of camera keyframes", "cameras");
  else
    for (size_t i = 0; i < cameras.size(); ++i) out.push_back(load::read_camera(cameras.item(i), diag, true));
  return out;
}

}  // namespace

namespace load {
void read_run_file(MapReader& root, RunFileSpec& out, Diagnostics& diag, bool campaign) {
  out.description = load::text(root.take("description"), "description", diag);
  out.vault = load::scalar(root.require("vault"), "vault", diag);
  if (out.vault.present && !out.vault.null) {
    fs::path p(out.vault.text);
    out.vault_path = join_path(fs::path(out.path).parent_path().string(), p.string());
    if (std::string why = outside_roots(out.vault_path); !why.empty())
      diag.error(out.vault.mark, fmt::format("vault file '{}' {}", out.vault.text, why));
  }
  MapReader set(root.take("set"), "set", diag);
  for (auto& [k, v] : set.rest()) out.set.emplace_back(load::name(k, "a parameter", diag), load::scalar(v, "a parameter value", diag));
  MapReader sim(root.take("sim"), "sim", diag);
  out.timestep = load::scalar(sim.take("timestep"), "timestep", diag);
  out.gravity = load::boolean(sim.take("gravity"), "gravity", diag, true);
  out.limit = load::scalar(sim.take("limit"), "limit", diag);
  out.check_tolerance = load::scalar(sim.take("check_tolerance"), "check_tolerance", diag);
  out.mode = load::scalar(sim.take("mode"), "mode", diag);
  if (campaign) out.seed = load::scalar(sim.take("seed"), "seed", diag);
  if (sim.ok()) sim.finish();
  MapReader record(root.take("record"), "record", diag);
  if (record.ok()) {
    MapReader traj(record.take("trajectory"), "trajectory", diag);
    out.trajectory_rate = load::scalar(traj.take("rate"), "trajectory rate", diag);
    if (traj.ok()) traj.finish();
    yaml::Node frames = record.take("frames");
    if (frames.valid()) {
      out.frames = true;
      MapReader f(frames, "frames", diag);
      out.fps = load::scalar(f.take("fps"), "fps", diag);
      out.width = load::scalar(f.take("width"), "width", diag);
      out.height = load::scalar(f.take("height"), "height", diag);
      if (f.ok()) f.finish();
    }
    record.finish();
  }
  out.cameras = read_cameras(root.take("cameras"), diag);
}

}  // namespace load


std::optional<std::vector<CameraKeySpec>> load_cameras(const std::string& path, Sources& sources, Diagnostics& diag) {
  uint32_t file = read_source(path, sources, diag);
  if (file == 0) return std::nullopt;
  yaml::Document doc = yaml::parse(sources, file, diag);
  if (doc.empty()) return std::nullopt;
  MapReader root(doc.root(), "a camera file", diag);
  if (!root.ok()) return std::nullopt;
  load::check_version(root, diag);
  std::vector<CameraKeySpec> keys = read_cameras(root.require("cameras"), diag);
  root.finish();
  return keys;
}

std::optional<ScenarioSpec> load_scenario(const std::string& path, Sources& sources, Diagnostics& diag) {
  uint32_t file = read_source(path, sources, diag);
  if (file == 0) return std::nullopt;
  return load_scenario(file, sources, diag);
}

namespace {
bool is_campaign(const yaml::Document& doc) {
  return !doc.empty() && doc.root().is_map() && doc.root().find("campaign").valid() && !doc.root().find("scenario").valid();
}
}  // namespace

std::optional<std::variant<ScenarioSpec, CampaignSpec>> load_run_file(const std::string& path, Sources& sources, Diagnostics& diag) {
  uint32_t file = read_source(path, sources, diag);
  if (file == 0) return std::nullopt;
  Diagnostics peek;  // the loader reports what parsing finds
  if (is_campaign(yaml::parse(sources, file, peek))) {
    if (auto c = load_campaign(file, sources, diag)) return std::variant<ScenarioSpec, CampaignSpec>(std::move(*c));
    return std::nullopt;
  }
  if (auto s = load_scenario(file, sources, diag)) return std::variant<ScenarioSpec, CampaignSpec>(std::move(*s));
  return std::nullopt;
}

std::optional<ScenarioSpec> load_scenario(uint32_t file, Sources& sources, Diagnostics& diag) {
  yaml::Document doc = yaml::parse(sources, file, diag);
  if (doc.empty()) return std::nullopt;
  // A campaign file (campaign-format.md) where only a scenario can go (a sweep's `scenario:`):
  // loaded and checked as one, and saying so beats "missing key 'scenario'".
  if (is_campaign(doc)) {
    load_campaign(file, sources, diag);
    diag.error(doc.root().find("campaign").mark(),
               "this is a campaign file (campaign-format.md): `sscs simulate` runs it, but a scenario is expected here");
    return std::nullopt;
  }
  MapReader root(doc.root(), "a scenario file", diag);
  if (!root.ok()) return std::nullopt;
  load::check_version(root, diag);
  ScenarioSpec sc;
  sc.path = sources.path(file);
  yaml::Node name = root.require("scenario");
  sc.name = load::name(name, "the scenario", diag);
  sc.mark = name.valid() ? name.mark() : root.mark();
  load::read_run_file(root, sc, diag, false);
  sc.steps = load::read_steps(root.require("steps"), diag, false);
  root.finish();
  return sc;
}

}  // namespace sscs
