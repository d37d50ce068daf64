#include "pipeline/scenario.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include <fmt/format.h>

#include "compile/values.h"
#include "core/limits.h"
#include "core/names.h"
#include "model/device.h"

namespace sscs {

namespace {

constexpr double kCoarseTimestep = 0.01;  // s: above it a run's verdicts are warned of (measured in Articulated.MotorsTrack...)
static_assert(std::variant_size_v<decltype(StepSpec::action)> == std::size(kStepActionNames));

class ScenarioCompiler {
 public:
  ScenarioCompiler(const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag) : wc_(wc), geometry_(geometry), diag_(diag) {}

  ScenarioCommands run(const ScenarioSpec& spec) {
    ScenarioCommands out;
    out.settings = settings(spec);
    for (size_t i = 0; i < spec.steps.size(); ++i) {
      const StepSpec& step = spec.steps[i];
      if (const auto* par = std::get_if<ParallelSpec>(&step.action)) {
        StepCommand group;
        group.index = i;
        group.kind = StepKind::Parallel;
        group.mark = step.mark;
        std::map<int, SourceMark> devices;
        for (const StepSpec& member : par->steps) {
          StepCommand c = command(member, i);
          if (c.device >= 0 && !devices.emplace(c.device, member.mark).second)
            diag_.error(member.mark, fmt::format("{} has two steps in one parallel group", wc_.objects[c.device].name));
          group.members.push_back(std::move(c));
        }
        out.steps.push_back(std::move(group));
      } else {
        out.steps.push_back(command(step, i));
      }
      if (diag_.full()) break;
    }
    return out;
  }

  SimSettings settings(const RunFileSpec& spec) {
    SimSettings s;
    auto positive = [&](const Scalar& v, Dim dim, const char* what, double& out) {
      if (!v.present) return;
      auto x = literal_si(v, dim, what, diag_);
      if (x && !(*x > 0)) diag_.error(v.mark, fmt::format("{} must be positive, found {}", what, v.text));
      else if (x) out = *x;
    };
    positive(spec.timestep, Dim::Time, "sim.timestep", s.timestep);
    positive(spec.limit, Dim::Time, "sim.limit", s.limit);
    if (spec.check_tolerance.present) {
      auto x = literal_si(spec.check_tolerance, Dim::Length, "sim.check_tolerance", diag_);
      if (x && !(*x >= 0 && *x <= 0.01))
        diag_.error(spec.check_tolerance.mark, fmt::format("sim.check_tolerance must be between 0 and 10 mm, found {}", spec.check_tolerance.text));
      else if (x) s.check_tolerance = *x;
    }
    positive(spec.trajectory_rate, Dim::Frequency, "trajectory rate", s.rate);
    if (spec.mode.present) {
      if (spec.mode.text == "fast") s.mode = SimMode::Fast;
      else if (spec.mode.text != "physics")
        diag_.error(spec.mode.mark, fmt::format("sim.mode must be physics or fast, found '{}'{}", spec.mode.text,
                                                did_you_mean(spec.mode.text, {"physics", "fast"})));
    }
    s.gravity = spec.gravity;
    s.frames = spec.frames;
    auto count = [&](const Scalar& v, const char* what, int& out) {
      double x = out;
      positive(v, Dim::None, what, x);
      if (v.present && (x != std::floor(x) || x > 100000)) diag_.error(v.mark, fmt::format("{} must be a whole number, found {}", what, v.text));
      out = static_cast<int>(x);
    };
    count(spec.fps, "fps", s.fps);
    count(spec.width, "width", s.width);
    count(spec.height, "height", s.height);
    // Frames are rendered offscreen: the same bounds as `render --size` (100000 x 100000 ended
    // in bad_alloc).
    for (const auto& [v, value, what] : {std::tuple{&spec.width, s.width, "record.frames.width"},
                                         std::tuple{&spec.height, s.height, "record.frames.height"}})
      if (v->present && (value < 16 || value > 8192))
        diag_.error(v->mark, fmt::format("{} must be between 16 and 8192 pixels, found {}", what, v->text));
    if (spec.fps.present && s.fps > 1000) diag_.error(spec.fps.mark, fmt::format("record.frames.fps must be at most 1000, found {}", spec.fps.text));
    if (s.timestep > 0.1) diag_.error(spec.timestep.mark, fmt::format("sim.timestep {} is too coarse for contact physics (at most 100 ms)", spec.timestep.text));
    else if (s.timestep > kCoarseTimestep)
      diag_.warning(spec.timestep.mark, fmt::format("sim.timestep {} is coarse: contacts and the tracking of the plan are judged once "
                                                    "a step, and above {:g} ms a run can report collisions and tracking errors "
                                                    "the design does not have (the default is 1 ms)",
                                                    spec.timestep.text, kCoarseTimestep * 1000));
    return s;
  }

  /// One step, its names resolved and values read.
  StepCommand command(const StepSpec& step, size_t index) {
    StepCommand c;
    c.index = index;
    c.kind = static_cast<StepKind>(step.action.index());
    c.mark = step.mark;
    if (const auto* w = std::get_if<WaitSpec>(&step.action)) {
      auto d = literal_si(w->duration, Dim::Time, "wait", diag_);
      if (d && *d < 0) diag_.error(w->duration.mark, fmt::format("wait must not be negative, found {}", w->duration.text));
      c.duration = std::max(d.value_or(0), 0.0);
      return c;
    }
    c.device = step.device.present ? device(step.device) : -1;
    if (c.device < 0) return c;
    const int d = c.device;
    const Device& m = *geometry_.objects[d].device;
    if (const auto* mj = std::get_if<MoveJointsSpec>(&step.action)) {
      c.home = mj->home;
      const ObjectType& type = wc_.types[wc_.objects[d].type];
      for (size_t i = 0; i < mj->joints.size(); ++i) {
        const auto& [name, value] = mj->joints[i];
        int k = -1;
        std::vector<std::string> names;
        for (int j = 0; j < m.dof(); ++j) {
          names.push_back(m.joint(j).name);
          if (m.joint(j).name == name) k = j;
        }
        if (k < 0) {
          diag_.error(mj->joint_marks[i], fmt::format("'{}' is not a joint of {} ({}); its joints: {}{}", name,
                                                     wc_.objects[d].name, type.name, fmt::join(names, ", "), did_you_mean(name, names)));
          continue;
        }
        const Joint& j = m.joint(k);
        Dim dim = j.type == JointType::Revolute ? Dim::Angle : Dim::Length;
        auto v = literal_si(value, dim, fmt::format("joint '{}'", name), diag_);
        if (!v) continue;
        auto in = within_bounds(*v, j.lower, j.upper);  // a limit copied from `sscs types` is the limit
        if (!in) {
          diag_.error(value.mark, fmt::format("{} of {} is {}, outside its limits [{}, {}]", name, wc_.objects[d].name,
                                              with_unit(*v, dim), with_unit(j.lower, dim), with_unit(j.upper, dim)));
          continue;
        }
        c.joints.emplace_back(k, *in);
      }
      c.speed = speed_fraction(step, false);
    } else if (const auto* mt = std::get_if<MoveToSpec>(&step.action)) {
      target(mt->target, c);
      c.offset = literal_pose(mt->offset, "offset", diag_);
      c.linear = mt->linear;
      c.speed = speed_fraction(step, mt->linear);
      if (!c.pose && c.target < 0) c.device = -1;  // reported: the step is not planned
    } else if (const auto* g = std::get_if<GraspSpec>(&step.action)) {
      c.object = object(g->object, "grasp");
      c.object_text = g->object.text;
      c.object_mark = g->object.mark;
    } else if (const auto* r = std::get_if<ReleaseSpec>(&step.action)) {
      c.object = r->object.present ? object(r->object, "release") : -1;
      c.object_text = r->object.text;
      c.object_mark = r->object.mark;
    }
    return c;
  }

 private:
  /// The device named by a step, or -1 (reported).
  int device(const Scalar& s) {
    int o = object(s, "step device");
    if (o >= 0 && !geometry_.objects[o].device) {
      diag_.error(s.mark, fmt::format("'{}' is a {}, not a device", s.text, wc_.types[wc_.objects[o].type].name));
      return -1;
    }
    return o;
  }

  int object(const Scalar& s, std::string_view what) {
    if (!s.present || s.null) return -1;
    int o = wc_.find_object(s.text);
    if (o < 0) {
      std::vector<std::string> names;
      for (const Object& x : wc_.objects) names.push_back(x.name);
      diag_.error(s.mark, fmt::format("unknown object '{}' for {}{}", s.text, what, did_you_mean(s.text, names)));
    }
    return o;
  }

  /// `speed: 50%` scales the limits; absent is 100 %.
  double speed_fraction(const StepSpec& step, bool linear) {
    if (!step.speed.present) return 1.0;
    ParsedValue v = parse_value(step.speed, Dim::None, "speed", diag_, true);
    if (v.kind != ParsedValue::Kind::Number) return 1.0;
    if (v.dim == Dim::Velocity && linear) return v.si / kLinearSpeed;
    if (v.dim != Dim::Fraction || !(v.si > 0) || v.si > 1) {
      diag_.error(step.speed.mark, fmt::format("expected a speed as a percentage in (0%, 100%]{} for speed, found '{}'",
                                               linear ? " or a tool speed (0.25 m/s)" : "", step.speed.text));
      return 1.0;
    }
    return v.si;
  }

  /// A move_to target: a pose in the world, or an object's frame (`Obj` is its origin).
  void target(const TargetSpec& t, StepCommand& c) {
    if (t.pose) {
      c.pose = literal_pose(*t.pose, "move_to target", diag_);
      return;
    }
    const std::string& text = t.ref.text;
    auto dot = text.rfind('.');
    Scalar obj = t.ref;
    std::string frame = "origin";
    if (dot != std::string::npos) {
      obj.text = text.substr(0, dot);
      frame = text.substr(dot + 1);
    }
    int o = object(obj, "move_to target");
    if (o < 0) return;
    std::vector<std::string> names = wc_.frame_names(o);
    if (std::find(names.begin(), names.end(), frame) == names.end()) {
      diag_.error(mark_at(t.ref, dot + 1), fmt::format("'{}' is not a frame of {}; its frames: {}{}", frame, obj.text,
                                                      name_list(names), did_you_mean(frame, names)));
      return;
    }
    c.target = o;
    c.frame = frame;
  }

  const Workcell& wc_;
  const GeometryModel& geometry_;
  Diagnostics& diag_;
};

}  // namespace

StepCommand compile_step(const StepSpec& step, size_t index, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag) {
  return ScenarioCompiler(wc, geometry, diag).command(step, index);
}

SimSettings compile_settings(const RunFileSpec& spec, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag) {
  return ScenarioCompiler(wc, geometry, diag).settings(spec);
}

ScenarioCommands compile_scenario(const ScenarioSpec& spec, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag) {
  return ScenarioCompiler(wc, geometry, diag).run(spec);
}

std::optional<Plan> plan_scenario(const ScenarioSpec& spec, const Workcell& wc, const GeometryModel& geometry, Diagnostics& diag) {
  return plan_scenario(compile_scenario(spec, wc, geometry, diag), wc, geometry, diag);
}

}  // namespace sscs
