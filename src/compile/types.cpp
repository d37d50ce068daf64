// Pass 1: the type library. Load type files, resolve `extends`, merge attributes, add joints.
#include <algorithm>
#include <functional>
#include <map>
#include <numbers>
#include <set>

#include <fmt/format.h>

#include "compile/compile.h"
#include "compile/templates.h"
#include "compile/values.h"
#include "core/expr.h"
#include "core/names.h"


namespace sscs {

int ObjectType::find_attribute(std::string_view n) const {
  for (size_t i = 0; i < attributes.size(); ++i)
    if (attributes[i].name == n) return static_cast<int>(i);
  return -1;
}

namespace {

AttributeDef make_attribute(const AttributeDecl& decl, Diagnostics& diag) {
  AttributeDef a;
  a.name = decl.name;
  a.type = decl.type;
  a.dim = dim_of(decl.type);
  a.values = decl.values;
  a.description = decl.description;
  a.default_value = decl.default_value;
  a.mark = decl.mark;
  bool numeric = decl.type != AttrType::String && decl.type != AttrType::Enum && decl.type != AttrType::Boolean;
  for (auto [scalar, out, word] : {std::tuple{&decl.min, &a.min_si, "min"}, std::tuple{&decl.max, &a.max_si, "max"}}) {
    if (!scalar->present) continue;
    if (!numeric) {
      diag.error(scalar->mark, fmt::format("'{}' is only allowed for numeric attributes", word));
      continue;
    }
    *out = literal_si(*scalar, a.dim, fmt::format("the {} of '{}'", word, a.name), diag);
  }
  if (a.min_si && a.max_si && *a.min_si > *a.max_si)
    diag.error(decl.max.mark, fmt::format("max of '{}' is below its min", a.name));
  if (decl.type == AttrType::Enum && decl.default_value.present &&
      std::find(decl.values.begin(), decl.values.end(), decl.default_value.text) == decl.values.end())
    diag.error(decl.default_value.mark, fmt::format("default '{}' of '{}' is not one of its values ({})",
                                                    decl.default_value.text, a.name, fmt::join(decl.values, ", ")));
  return a;
}

ValueRef compile_value(const Scalar& v, Dim dim, const ObjectType& type, std::string_view what, Diagnostics& diag,
                       const std::vector<std::string>& counters = {});

/// A joint limit: a number with its unit, or an expression over the type's attributes that are
/// no joints (evaluated for each object).
void joint_limit(const Scalar& v, const AttributeDef& a, const ObjectType& type, std::optional<double>& si, ValueRef& expr,
                 std::string_view what, Diagnostics& diag) {
  if (!v.present) return;
  Diagnostics quiet;
  if (parse_value(v, a.dim, what, quiet).kind != ParsedValue::Kind::Expression) {
    si = literal_si(v, a.dim, what, diag);
    return;
  }
  expr = compile_value(v, a.dim, type, what, diag);
  for (int k : expr.attributes)
    if (k >= 0 && k < static_cast<int>(type.attributes.size()) && type.attributes[k].joint)
      diag.error(v.mark, fmt::format("{} uses joint '{}'; a limit may use the type's attributes, not its joints", what, type.attributes[k].name));
}

/// Joint values are attributes of a device instance, limited by the joint's limits.
void add_joint_attributes(const TypeSpec& spec, ObjectType& type, Diagnostics& diag) {
  const DeviceSpec& device = *spec.device;
  for (const PartSpec& part : device.parts) {
    if (!part.joint || part.joint->type == JointType::Fixed) continue;
    const JointSpec& j = *part.joint;
    AttributeDef a;
    a.name = j.name;
    a.type = j.type == JointType::Revolute ? AttrType::Angle : AttrType::Length;
    a.dim = dim_of(a.type);
    a.mark = j.mark;
    a.joint = true;
    a.description = fmt::format("{} joint of part '{}'", j.type == JointType::Revolute ? "revolute" : "prismatic", part.name);
    joint_limit(j.min, a, type, a.min_si, a.min_expr, fmt::format("the min of joint '{}'", j.name), diag);
    joint_limit(j.max, a, type, a.max_si, a.max_expr, fmt::format("the max of joint '{}'", j.name), diag);
    if (is_object_key(a.name)) {
      diag.error(j.mark, fmt::format("joint '{}' has the name of a key of every object (an object could not set it){}", j.name,
                                     spec.device->urdf.present ? fmt::format("; rename it in '{}'", spec.device->urdf.text) : ""));
      continue;
    }
    if (type.find_attribute(a.name) >= 0) {
      diag.error(j.mark, fmt::format("joint '{}' has the name of an attribute of '{}'", j.name, type.name));
      continue;
    }
    // The default is the home value, else 0 (or the nearest limit when 0 is outside them).
    auto home = std::find_if(device.home.begin(), device.home.end(), [&](const auto& h) { return h.first == j.name; });
    if (home != device.home.end()) {
      a.default_value = home->second;
      // A number with its unit: `move_joints: home` needs the value itself, for every instance.
      a.home_si = literal_si(home->second, a.dim, fmt::format("the home value of joint '{}'", j.name), diag).value_or(0);
      // The type's fault, at its home line (it was reported at every vault object using the type).
      const double lo = a.min_si.value_or(-INFINITY), hi = a.max_si.value_or(INFINITY);
      if (auto in = within_bounds(a.home_si, lo, hi)) a.home_si = *in;
      else
        diag.error(home->second.mark, fmt::format("the home value of joint '{}' is {}, {} {}{}", j.name, with_unit(a.home_si, a.dim),
                                                  a.home_si < lo ? "below its min" : "above its max",
                                                  with_unit(a.home_si < lo ? lo : hi, a.dim),
                                                  j.soft_limited ? " (the URDF's soft limits apply: `joint_limits: hard` uses <limit>)" : ""));
    } else {
      double zero = 0;
      if (a.min_si && zero < *a.min_si) zero = *a.min_si;
      if (a.max_si && zero > *a.max_si) zero = *a.max_si;
      a.default_value.present = true;
      a.default_value.mark = j.mark;
      a.default_value.text = fmt::format("{}", a.type == AttrType::Angle ? zero * 180.0 / std::numbers::pi : zero);
      a.home_si = zero;
    }
    type.attributes.push_back(std::move(a));
  }
  std::vector<std::string> joints;
  for (const AttributeDef& a : type.attributes)
    if (a.joint) joints.push_back(a.name);
  for (const auto& [joint, value] : device.home)
    if (type.find_attribute(joint) < 0 || !type.attributes[type.find_attribute(joint)].joint)
      diag.error(value.mark, fmt::format("home names '{}', which is not a joint of '{}'{}", joint, type.name, did_you_mean(joint, joints)));
}

/// Compiles a value of a type's geometry, frames or parts: a number, a unit literal, or an
/// expression over the type's own attributes. What it cannot read is an error (the type's
/// problem) and a NaN constant.
ValueRef compile_value(const Scalar& v, Dim dim, const ObjectType& type, std::string_view what, Diagnostics& diag,
                       const std::vector<std::string>& counters) {
  ValueRef out;
  if (!v.present) return out;
  out.present = true;
  out.text = v.text;
  out.mark = v.mark;
  ParsedValue parsed = parse_value(v, dim, what, diag);
  if (parsed.kind == ParsedValue::Kind::Number) out.constant = parsed.si;
  if (parsed.kind != ParsedValue::Kind::Expression) return out;
  Expression::Error err;
  auto expr = Expression::parse(v.text, &err);
  if (!expr) {
    diag.error(mark_at(v, err.position), fmt::format("cannot read '{}' as a value or expression for {}: {}", v.text, what, err.message));
    return out;
  }
  std::vector<std::string> names = counters;
  for (const AttributeDef& a : type.attributes) names.push_back(a.name);
  for (const std::string& n : expr->names()) {
    if (auto c = std::find(counters.begin(), counters.end(), n); c != counters.end()) {
      out.attributes.push_back(ValueRef::kCounter + static_cast<int>(c - counters.begin()));
      continue;
    }
    int a = type.find_attribute(n);
    if (a < 0) {
      diag.error(mark_at(v, v.text.find(n)), fmt::format("{} uses '{}', which is not an attribute of type '{}'{}", what, n,
                                                         type.name, did_you_mean(n, names)));
    } else if (type.attributes[a].type == AttrType::String || type.attributes[a].type == AttrType::Enum) {
      diag.error(mark_at(v, v.text.find(n)), fmt::format("{} uses '{}', which is not numeric", what, n));
    }
    out.attributes.push_back(a);
  }
  check_expression_dimensions(*expr, [&](std::string_view n) -> std::optional<Dim> {
    int a = type.find_attribute(n);
    if (a < 0 || type.attributes[a].dim == Dim::None) return std::nullopt;  // a counter, a plain number
    return type.attributes[a].dim;
  }, v, dim, what, diag);
  out.expr = std::make_shared<const Expression>(std::move(*expr));
  return out;
}

VectorRef compile_vector(const std::array<Scalar, 3>& v, Dim dim, const ObjectType& type, std::string_view what, Diagnostics& diag,
                         const std::vector<std::string>& counters = {}) {
  VectorRef out;
  for (int k = 0; k < 3; ++k) out.v[k] = compile_value(v[k], dim, type, what, diag, counters);
  return out;
}

PoseRef compile_pose(const PoseSpec& pose, const ObjectType& type, std::string_view what, Diagnostics& diag,
                     const std::vector<std::string>& counters = {}) {
  return {compile_vector(pose.xyz, Dim::Length, type, fmt::format("{} xyz", what), diag, counters),
          compile_vector(pose.rpy, Dim::Angle, type, fmt::format("{} rpy", what), diag, counters)};
}

/// The names a repeated entry's values may use besides the type's attributes.
std::vector<std::string> counter_names(const std::optional<RepeatSpec>& repeat) {
  std::vector<std::string> out;
  if (repeat)
    for (const RepeatSpec::Counter& c : repeat->counters) out.push_back(c.name);
  return out;
}

/// A repeat's counts and pitches, over the type's attributes; a counter named as an attribute
/// would hide it.
std::shared_ptr<const RepeatTemplate> compile_repeat(const std::optional<RepeatSpec>& repeat, const ObjectType& type,
                                                     Diagnostics& diag) {
  if (!repeat) return nullptr;
  auto out = std::make_shared<RepeatTemplate>();
  out->mark = repeat->mark;
  for (const RepeatSpec::Counter& c : repeat->counters) {
    if (type.find_attribute(c.name) >= 0)
      diag.error(c.mark, fmt::format("repeat counter '{}' has the name of an attribute of '{}' (a counter would hide it)", c.name, type.name));
    RepeatTemplate::Counter& t = out->counters.emplace_back();
    t.name = c.name;
    t.count = compile_value(c.count, Dim::None, type, fmt::format("the count of repeat counter '{}'", c.name), diag);
    t.pitch = compile_vector(c.pitch, Dim::Length, type, fmt::format("the pitch of repeat counter '{}'", c.name), diag);
  }
  return out;
}

/// Compiles geometry entries; a mesh file that cannot be read goes to `deferred` (the type's
/// problems, reported when it is used).
std::vector<ShapeTemplate> compile_geometry(const std::vector<GeometrySpec>& geometry, const ObjectType& type, const std::string& type_file,
                                            const FileFacts& files, Diagnostics& diag, std::vector<Diagnostic>& deferred) {
  std::vector<ShapeTemplate> out;
  for (const GeometrySpec& g : geometry) {
    ShapeTemplate t;
    const std::vector<std::string> counters = counter_names(g.repeat);
    std::visit(
        [&](const auto& shape) {
          using T = std::decay_t<decltype(shape)>;
          if constexpr (std::is_same_v<T, BoxSpec>) {
            t.kind = ShapeTemplate::Kind::Box;
            t.size = compile_vector(shape.size, Dim::Length, type, "box size", diag, counters);
          } else if constexpr (std::is_same_v<T, CylinderSpec>) {
            t.kind = ShapeTemplate::Kind::Cylinder;
            t.radius = compile_value(shape.radius, Dim::Length, type, "cylinder radius", diag, counters);
            t.length = compile_value(shape.length, Dim::Length, type, "cylinder length", diag, counters);
          } else if constexpr (std::is_same_v<T, SphereSpec>) {
            t.kind = ShapeTemplate::Kind::Sphere;
            t.radius = compile_value(shape.radius, Dim::Length, type, "sphere radius", diag, counters);
          } else {
            t.kind = ShapeTemplate::Kind::Mesh;
            t.scale = compile_vector(shape.scale, Dim::None, type, "mesh scale", diag, counters);
            t.mesh_text = shape.file.text;
            t.mesh_mark = shape.file.mark;
            t.mesh_file = files.mesh_path(type_file, shape.file.text);
            if (shape.file.present)
              if (std::string why = files.why_unreadable(t.mesh_file); !why.empty())
                deferred.push_back({shape.file.mark, fmt::format("mesh file '{}' {}", shape.file.text, why)});
          }
        },
        g.shape);
    t.pose = compile_pose(g.pose, type, "geometry", diag, counters);
    t.repeat = compile_repeat(g.repeat, type, diag);
    t.color = g.color;
    out.push_back(std::move(t));
  }
  return out;
}

/// A device's parts form one tree: unique names, one root, known parents, no cycles, a real tool.
/// Compiled to its template.
std::shared_ptr<const DeviceTemplate> compile_device(const DeviceSpec& d, const ObjectType& type, const std::string& type_file,
                                                     const FileFacts& files, Diagnostics& diag, std::vector<Diagnostic>& deferred) {
  std::map<std::string, const PartSpec*> parts;
  std::vector<std::string> names;
  std::map<std::string, SourceMark> joints;
  for (const PartSpec& p : d.parts) {
    if (!parts.emplace(p.name, &p).second) diag.error(p.mark, fmt::format("part name '{}' is used twice", p.name));
    names.push_back(p.name);
    if (p.joint && !joints.emplace(p.joint->name, p.joint->mark).second)
      diag.error(p.joint->mark, fmt::format("joint name '{}' is used twice", p.joint->name));
  }
  const PartSpec* root = nullptr;
  for (const PartSpec& p : d.parts) {
    if (p.parent.empty()) {
      if (root) diag.error(p.mark, fmt::format("device '{}' has two root parts ('{}' and '{}'); every other part needs a parent",
                                               type.name, root->name, p.name));
      else root = &p;
    } else if (!parts.count(p.parent)) {
      diag.error(p.parent_mark, fmt::format("part '{}' has unknown parent '{}'{}", p.name, p.parent, did_you_mean(p.parent, names)));
    }
    // Walk up: a cycle never reaches the root.
    const PartSpec* cur = &p;
    for (size_t steps = 0; cur && !cur->parent.empty(); ++steps) {
      auto it = parts.find(cur->parent);
      cur = it == parts.end() ? nullptr : it->second;
      if (steps > d.parts.size()) {
        diag.error(p.mark, fmt::format("parts of device '{}' form a cycle through '{}'", type.name, p.name));
        break;
      }
    }
    if (p.joint) {
      const JointSpec& j = *p.joint;
      if (j.type != JointType::Fixed && j.axis[0].present) {
        double norm = 0;
        bool numeric = true;
        for (const Scalar& c : j.axis) {
          auto v = parse_number(c.text);
          if (!v) numeric = false;
          else norm += *v * *v;
        }
        if (!numeric) diag.error(j.axis[0].mark, fmt::format("joint '{}' axis must be three numbers", j.name));
        else if (norm < 1e-18) diag.error(j.axis[0].mark, fmt::format("joint '{}' has a zero axis", j.name));
      }
    }
    if (p.color.present && !p.color.null && !is_valid_color(p.color.text))
      diag.error(p.color.mark, fmt::format("expected a colour \"#RRGGBB\" for part '{}', found '{}'", p.name, p.color.text));
  }
  if (!d.parts.empty() && !root) diag.error(d.parts[0].mark, fmt::format("device '{}' has no root part (one part without a parent)", type.name));
  // Allowed collisions name two different parts of this device (an SRDF of another robot, or a
  // typo, would otherwise leave a real self-collision unchecked or a listed pair meaningless).
  // An SRDF's are reported where the type is used, as the URDF's problems are.
  for (const DeviceSpec::AllowedCollision& pair : d.allowed_collisions) {
    const bool from_srdf = d.srdf.present && pair.mark.file != d.srdf.mark.file;
    auto report = [&](std::string message) {
      if (from_srdf) deferred.push_back({pair.mark, std::move(message)});
      else diag.error(pair.mark, std::move(message));
    };
    for (const std::string* name : {&pair.a, &pair.b})
      if (!name->empty() && !parts.count(*name))
        report(fmt::format("{} names '{}', which is no {} of '{}'{}", from_srdf ? "this <disable_collisions>" : "allowed_collisions", *name,
                           from_srdf ? "link" : "part", type.name, from_srdf ? " (is the SRDF another robot's?)" : did_you_mean(*name, names)));
    if (!pair.a.empty() && pair.a == pair.b)
      report(fmt::format("an allowed collision pairs two different parts, found '{}' twice", pair.a));
  }
  if (!d.tool_part.empty() && !parts.count(d.tool_part)) {
    if (d.srdf.present && d.tool_mark.file != d.srdf.mark.file)  // the SRDF's end effector or chain tip
      deferred.push_back({d.tool_mark, fmt::format("the tool this SRDF names, '{}', is no link of '{}' (is the SRDF another robot's?)",
                                                   d.tool_part, type.name)});
    else
      diag.error(d.tool_mark, fmt::format("tool part '{}' is not a part of '{}'{}", d.tool_part, type.name, did_you_mean(d.tool_part, names)));
  }

  // The template: the parts in the file's order, and the order to build them in.
  auto dt = std::make_shared<DeviceTemplate>();
  dt->kinematic = d.kinematic;
  dt->from_urdf = d.urdf.present;
  dt->urdf = d.urdf.present ? d.urdf.text : "";
  dt->srdf = d.srdf.present ? d.srdf.text : "";
  dt->hard_limits = d.hard_limits;
  dt->urdf_mesh_refs = d.urdf_mesh_refs;
  auto find = [&](const std::string& name) {
    for (size_t k = 0; k < d.parts.size(); ++k)
      if (d.parts[k].name == name) return static_cast<int>(k);
    return -1;
  };
  for (const PartSpec& p : d.parts) {
    PartTemplate& pt = dt->parts.emplace_back();
    pt.name = p.name;
    pt.parent = p.parent.empty() ? -1 : find(p.parent);
    if (p.joint) {
      const JointSpec& js = *p.joint;
      JointTemplate& j = pt.joint.emplace();
      j.name = js.name;
      j.type = js.type;
      j.origin = compile_pose(js.origin, type, fmt::format("joint '{}'", js.name), diag);
      if (js.type != JointType::Fixed) {
        j.axis = compile_vector(js.axis, Dim::None, type, fmt::format("joint '{}' axis", js.name), diag);
        const Dim rate = js.type == JointType::Revolute ? Dim::Angle : Dim::Length;
        j.velocity = compile_value(js.velocity, rate, type, fmt::format("joint '{}' velocity", js.name), diag);
        j.acceleration = compile_value(js.acceleration, rate, type, fmt::format("joint '{}' acceleration", js.name), diag);
        j.effort = compile_value(js.effort, Dim::None, type, fmt::format("joint '{}' effort", js.name), diag);
      }
      if (js.type != JointType::Fixed) dt->joint_parts.push_back(static_cast<int>(dt->parts.size() - 1));
    }
    pt.shapes = compile_geometry(p.geometry, type, type_file, files, diag, deferred);
    pt.visual_shapes = compile_geometry(p.visual, type, type_file, files, diag, deferred);
    pt.mass = compile_value(p.mass, Dim::Mass, type, fmt::format("the mass of part '{}'", p.name), diag);
    pt.color = p.color.text;
    if (p.inertial) {
      PartTemplate::Inertial& in = pt.inertial.emplace();
      in.origin = compile_pose(p.inertial->origin, type, fmt::format("the inertial origin of part '{}'", p.name), diag);
      for (int k = 0; k < 6; ++k)
        in.inertia[k] = compile_value(p.inertial->inertia[k], Dim::None, type, fmt::format("the inertia of part '{}'", p.name), diag);
    }
  }
  // Parents before children, from the root, each part once (a broken tree, with names used twice
  // or a cycle, never loops here; what it leaves out is never built: the type's errors stop every
  // vault using it).
  std::vector<char> placed(dt->parts.size(), 0);
  for (size_t k = 0; k < dt->parts.size(); ++k)
    if (d.parts[k].parent.empty()) {
      dt->build_order.push_back(static_cast<int>(k));
      placed[k] = 1;
    }
  for (size_t i = 0; i < dt->build_order.size(); ++i)
    for (size_t k = 0; k < dt->parts.size(); ++k)
      if (!placed[k] && !d.parts[k].parent.empty() && d.parts[k].parent == d.parts[dt->build_order[i]].name) {
        dt->build_order.push_back(static_cast<int>(k));
        placed[k] = 1;
      }
  for (const DeviceSpec::AllowedCollision& pair : d.allowed_collisions) {
    dt->allowed_names.emplace_back(pair.a, pair.b);
    int a = find(pair.a), b = find(pair.b);
    if (a >= 0 && b >= 0 && a != b) dt->allowed.emplace_back(std::min(a, b), std::max(a, b));
  }
  dt->tool_part = d.tool_part.empty() ? -1 : find(d.tool_part);
  dt->tool_pose = compile_pose(d.tool_pose, type, "tool", diag);
  return dt;
}

}  // namespace

std::vector<ObjectType> build_library(const LibraryInputs& in, Sources& sources, Diagnostics& diag, const std::set<std::string>* wanted) {
  const std::vector<std::shared_ptr<const TypeSpec>>& specs = in.specs;
  const std::map<std::string, std::vector<Diagnostic>>& file_problems = in.problems;
  const std::set<uint32_t>& plugin_files = in.plugin_files;
  std::map<std::string, size_t> index;  // name -> specs index (ordered: deterministic)
  for (size_t i = 0; i < specs.size(); ++i) index.emplace(specs[i]->name, i);

  // Resolve `extends` in dependency order; a cycle is reported once, at the type that closes it.
  std::vector<ObjectType> types(specs.size());
  std::vector<int> state(specs.size(), 0);  // 0 new, 1 resolving, 2 done
  std::vector<std::string> names;
  for (const auto& [n, i] : index) names.push_back(n);
  // The types whose templates are compiled: those wanted and every type they extend.
  // A plugin's types too, used or not: one that does not resolve is the plugin's fault (below).
  std::vector<char> shape(specs.size(), wanted == nullptr);
  std::vector<std::string> shaped;
  if (wanted) shaped.assign(wanted->begin(), wanted->end());
  for (const auto& spec : specs)
    if (!spec->plugin.empty()) shaped.push_back(spec->name);
  for (const std::string& w : shaped)
    for (auto it = index.find(w); it != index.end() && !shape[it->second]; it = index.find(specs[it->second]->extends))
      shape[it->second] = 1;
  std::function<bool(size_t)> resolve = [&](size_t i) -> bool {
    if (state[i] == 2) return true;
    const TypeSpec& spec = *specs[i];
    ObjectType& t = types[i];
    // A library type's errors (its file's, and those found resolving it) become its problems; a
    // plugin's go to `diag` (the plugin's fault: exit 3, below).
    Diagnostics own;
    Diagnostics& d = spec.plugin.empty() ? own : diag;
    auto done = [&] {
      for (const Diagnostic& w : own.warnings()) t.problems.push_back({w.mark, w.message, true});
      t.problems.insert(t.problems.end(), own.errors().begin(), own.errors().end());
      if (own.has_errors()) t.broken = true;
      state[i] = 2;
      return true;
    };
    if (state[i] == 1) return false;  // a cycle: the type that closes it reports it
    state[i] = 1;
    t.name = spec.name;
    t.description = spec.description;
    t.path = spec.path;
    t.extends = spec.extends;
    t.plugin = spec.plugin;
    t.device = spec.device.has_value();
    t.container = spec.container;
    t.zone = spec.zone;
    if (auto p = file_problems.find(spec.name); p != file_problems.end()) {
      t.problems = p->second;
      if (std::any_of(p->second.begin(), p->second.end(), [](const Diagnostic& x) { return !x.warning; })) {
        t.broken = true;
        state[i] = 2;
        return true;
      }
    }
    if (!spec.extends.empty()) {
      auto base = index.find(spec.extends);
      if (base == index.end()) {
        d.error(spec.extends_mark,
                fmt::format("type '{}' extends unknown type '{}'{}", spec.name, spec.extends, did_you_mean(spec.extends, names)));
        return done();
      }
      if (!resolve(base->second)) {
        d.error(spec.extends_mark, fmt::format("type '{}' extends itself through a cycle", spec.name));
        return done();
      }
      t.base = static_cast<int>(base->second);
      if (types[base->second].broken) {  // its problems are told with this type's, where it is used
        t.broken = true;
        return done();
      }
      t.attributes = types[base->second].attributes;
      t.templates = types[base->second].templates;  // flattened: its own replace them below
      t.device = t.device || types[base->second].device;
      t.container = t.container || types[base->second].container;
      t.zone = t.zone || types[base->second].zone;
    }
    // A container's geometry is all space: a column drawn into a room would stop nothing.
    if (t.container && spec.geometry.size() > 1)
      d.warning(spec.geometry[1].mark, fmt::format("type '{}' is a container (a space, as a room's box is its inside): all {} of its "
                                                   "shapes are space, none stops a device or a falling drum; make a solid inside "
                                                   "it, such as a column, an object of its own",
                                                   spec.name, spec.geometry.size()));
    for (const AttributeDecl& decl : spec.attributes) {
      AttributeDef a = make_attribute(decl, d);
      int existing = t.find_attribute(a.name);
      if (existing < 0) {
        t.attributes.push_back(std::move(a));
      } else if (t.attributes[existing].type != a.type) {
        d.error(decl.mark, fmt::format("attribute '{}' is a {} in the base type; '{}' cannot make it a {}", a.name,
                                       attr_type_name(t.attributes[existing].type), spec.name, attr_type_name(a.type)));
      } else {
        t.attributes[existing] = std::move(a);  // an override of the inherited default or limits
      }
    }
    // A device whose URDF or SRDF could not be imported has no parts to check its tool, home and
    // joints against: its import problems are what a vault using it is told.
    const bool imported = !spec.device || std::none_of(spec.device->import_problems.begin(), spec.device->import_problems.end(),
                                                       [](const Diagnostic& x) { return !x.warning; });
    if (spec.device && imported) add_joint_attributes(spec, t, d);
    if (!shape[i]) return done();  // (no object of it, nor of a type extending it)
    t.shaped = true;
    // Geometry, frames and parts are evaluated by later stages; their structure and the names
    // their expressions use are checked now, so a typo fails at load, with its line.
    TypeTemplates& tt = t.templates;
    if (spec.has_geometry || t.base < 0) tt.geometry = compile_geometry(spec.geometry, t, spec.path, in.files, d, t.problems);
    for (const RuleSpec& rule : spec.rules) {
      // A condition compares (`length - 1` for `length >= 1` held everywhere but at 1).
      if (rule.condition.present && rule.condition.text.find_first_of("<>=!&|") == std::string::npos)
        d.error(rule.condition.mark, fmt::format("a rule's condition compares or combines comparisons (==, !=, <, <=, >, >=, &&, ||, !), "
                                                 "found '{}': it would hold wherever it is not 0", rule.condition.text));
      tt.rules.push_back({compile_value(rule.condition, Dim::None, t, "a rule's condition", d), rule.message, spec.name});
    }
    if (spec.mass.present) {
      tt.mass = compile_value(spec.mass, Dim::Mass, t, "mass", d);
      tt.mass_type = spec.name;
    }
    for (const FrameSpec& f : spec.frames) {
      FrameTemplate frame{f.name, compile_pose(f.pose, t, fmt::format("frame '{}'", f.name), d, counter_names(f.repeat)),
                          compile_repeat(f.repeat, t, d), f.mark};
      auto same = std::find_if(tt.frames.begin(), tt.frames.end(), [&](const FrameTemplate& e) { return e.name == f.name; });
      if (same != tt.frames.end()) *same = std::move(frame);  // a subtype's frame replaces its base's
      else tt.frames.push_back(std::move(frame));
    }
    if (spec.device && imported) tt.device = compile_device(*spec.device, t, spec.path, in.files, d, t.problems);
    t.own_device = spec.device.has_value();
    for (const MeshSpec* m : named_meshes(spec)) t.own_meshes.push_back(m->file.text);
    tt.has_color = spec.color.present && !spec.color.null;  // its own: a colour is not inherited
    tt.color = spec.color.text;
    tt.color_mark = spec.color.mark;
    if (spec.device) {
      t.problems.insert(t.problems.end(), spec.device->import_problems.begin(), spec.device->import_problems.end());
      if (!imported) t.broken = true;
    }
    return done();
  };
  for (size_t i = 0; i < specs.size(); ++i) resolve(i);
  // A plugin type that does not resolve is the plugin's fault, not the vault's: exit 3.
  for (const Diagnostic& d : diag.errors())
    if (plugin_files.count(d.mark.file)) {
      Diagnostics mine;
      for (const Diagnostic& e : diag.errors())
        if (plugin_files.count(e.mark.file)) mine.error(e.mark, e.message);
      throw PluginError(fmt::format("a plugin's object type does not resolve against the type library:\n{}",
                                    mine.format(sources)));
    }
  return types;  // every type, in `specs` order (which `base` indexes); broken ones with their problems
}

}  // namespace sscs
