#include "pipeline/type_listing.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <tuple>
#include <numbers>

#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include "geometry/geometry.h"
#include "model/device.h"
#include "kinematics/envelope.h"
#include "load/load.h"
#include "core/pose.h"
#include "core/units.h"

namespace sscs {

TypeInstance instance_at_defaults(const std::shared_ptr<const std::vector<ObjectType>>& library, const ObjectType& type,
                                  const CompileOptions& base, Sources& sources, Diagnostics& problems) {
  TypeInstance out;
  Diagnostics diag;
  CompileOptions options = base;
  options.library = library;
  uint32_t file = sources.add("<types>", fmt::format("sscs: 1\nvault: types\nobjects:\n  - {{type: {}, name: Instance}}\n", type.name));
  auto spec = load_vault(file, sources, diag);
  std::optional<Workcell> wc;
  if (spec && !diag.has_errors()) wc = compile_vault(*spec, options, sources, diag);
  GeometryModel geometry;
  if (wc) geometry = build_geometry(*wc, diag);
  // Problems in the library's files are the library's (errors of the instance itself, such as a
  // required attribute, only say the type has no instance at its defaults).
  for (const Diagnostic& d : diag.warnings()) problems.warning(d.mark, d.message);
  for (const Diagnostic& d : diag.errors())
    if (d.mark.file != file) problems.error(d.mark, d.message);
  if (!wc || diag.has_errors() || geometry.objects.empty()) {
    out.unbuilt = diag.errors().empty() ? "it cannot be instanced" : diag.errors()[0].message;
    return out;
  }
  out.workcell = std::make_shared<const Workcell>(*wc);
  const ObjectGeometry& g = geometry.objects[0];
  out.bounds = g.bbox_world;  // the instance stands at the origin: world is the type's frame
  // `top` (what a reach or move_to targets by default), then the frames the type files name.
  out.frames.emplace_back("top", g.frame_pose("top"));
  // In the type files' order (a subtype's frame in its base's place), each copy of a repeated one.
  const double* attributes = &wc->values[wc->objects[0].first_slot + kFirstAttributeSlot];
  for (const FrameTemplate& f : wc->types[wc->objects[0].type].templates.frames)
    f.each(attributes, [&](const std::string& name, const Eigen::Isometry3d&) {
      if (const Eigen::Isometry3d* X = g.frame(name); X && name != "top") out.frames.emplace_back(name, *X);
    });
  const std::filesystem::path folder = std::filesystem::absolute(type.path).parent_path();
  auto add_mesh = [&](const Shape& s) {
    if (s.kind != Shape::Kind::Mesh || !s.mesh) return;
    std::string rel = std::filesystem::absolute(s.mesh->path).lexically_normal().lexically_relative(folder.lexically_normal()).string();
    if (rel.empty()) rel = s.mesh->path;
    for (const TypeInstance::Mesh& m : out.meshes)
      if (m.file == rel) return;
    out.meshes.push_back({rel, s.mesh->closed});
  };
  for (const Shape& s : g.shapes) add_mesh(s);
  if (g.device) {
    for (const Part& p : g.device->parts)
      for (const Shape& s : p.shapes) add_mesh(s);
    if (const Eigen::Isometry3d* X = g.frame("tool")) out.frames.emplace_back("tool", *X);
    out.reach = reach_envelope(*g.device, g.device->joint_values(&wc->values[wc->objects[0].first_slot + kFirstAttributeSlot]));
    for (int q = 0; q < g.device->dof(); ++q) {
      const Joint& j = g.device->joint(q);
      out.joints.push_back({j.name, j.type, j.max_speed(), j.max_acceleration(), j.velocity > 0, j.acceleration > 0});
    }
  }
  return out;
}

const char* joint_type_name(JointType t) {
  switch (t) {
    case JointType::Revolute: return "revolute";
    case JointType::Prismatic: return "prismatic";
    case JointType::Fixed: break;
  }
  return "fixed";
}

std::string vec_text(const Eigen::Vector3d& v) {
  return fmt::format("[{:.6g}, {:.6g}, {:.6g}]", stable(v.x()), stable(v.y()), stable(v.z()));
}

std::optional<Eigen::Vector3d> frame_rpy_deg(const Eigen::Isometry3d& X) {
  Eigen::Vector3d rpy = rotation_to_rpy(X.linear()) * (180 / std::numbers::pi);
  for (int k = 0; k < 3; ++k) rpy[k] = std::abs(rpy[k]) < 1e-9 ? 0.0 : rpy[k];
  if (rpy.isZero(1e-9)) return std::nullopt;
  return rpy;
}

namespace {

nlohmann::ordered_json vec_json(const Eigen::Vector3d& v) {
  auto j = nlohmann::ordered_json::array();
  for (int k = 0; k < 3; ++k) j.push_back(std::isfinite(v[k]) ? nlohmann::ordered_json(stable(v[k])) : nlohmann::ordered_json(nullptr));
  return j;
}

nlohmann::ordered_json type_json(const ObjectType& t, const std::vector<ObjectType>& types, const DeviceTemplate* device,
                                 const TypeInstance& instance) {
  nlohmann::ordered_json j;
  j["name"] = t.name;
  j["extends"] = t.base >= 0 ? types[t.base].name : "object";
  j["kind"] = t.device ? "device" : "object";
  j["description"] = t.description;
  j["plugin"] = t.plugin.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(t.plugin);
  auto attrs = nlohmann::ordered_json::array();
  for (const AttributeDef& a : t.attributes) {
    nlohmann::ordered_json aj;
    aj["name"] = a.name;
    aj["type"] = attr_type_name(a.type);
    aj["unit"] = file_unit(a.dim);
    aj["default"] = a.default_value.present ? nlohmann::ordered_json(a.default_value.text) : nullptr;
    // A joint limit written as an expression over the type's attributes: its text.
    aj["min"] = a.min_si ? nlohmann::ordered_json(stable(si_to_file(*a.min_si, a.dim)))
                : a.min_expr.present ? nlohmann::ordered_json(a.min_expr.text) : nullptr;
    aj["max"] = a.max_si ? nlohmann::ordered_json(stable(si_to_file(*a.max_si, a.dim)))
                : a.max_expr.present ? nlohmann::ordered_json(a.max_expr.text) : nullptr;
    if (a.type == AttrType::Enum) aj["values"] = a.values;
    aj["joint"] = a.joint;
    aj["description"] = a.description;
    attrs.push_back(std::move(aj));
  }
  j["attributes"] = std::move(attrs);
  // Where things are, at the default attributes, in the type's frame (m, deg).
  auto frames = nlohmann::ordered_json::array();
  for (const auto& [name, X] : instance.frames) {
    nlohmann::ordered_json fj = {{"name", name}, {"xyz", vec_json(X.translation())}};
    auto rpy = frame_rpy_deg(X);
    fj["rpy"] = rpy ? vec_json(*rpy) : vec_json(Eigen::Vector3d::Zero());
    frames.push_back(std::move(fj));
  }
  j["frames"] = std::move(frames);
  j["bounds"] = instance.bounds.isEmpty() ? nlohmann::ordered_json(nullptr)
                                           : nlohmann::ordered_json{{"min", vec_json(instance.bounds.min())}, {"max", vec_json(instance.bounds.max())}};
  auto meshes = nlohmann::ordered_json::array();
  for (const TypeInstance::Mesh& m : instance.meshes) meshes.push_back({{"file", m.file}, {"closed", m.closed}});
  j["meshes"] = std::move(meshes);
  j["unbuilt"] = instance.unbuilt.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(instance.unbuilt);
  if (device) {
    nlohmann::ordered_json dj;
    auto parts = nlohmann::ordered_json::array();
    for (const PartTemplate& p : device->parts) {
      nlohmann::ordered_json pj;
      pj["name"] = p.name;
      pj["parent"] = p.parent < 0 ? nullptr : nlohmann::ordered_json(device->parts[p.parent].name);
      if (p.joint) pj["joint"] = {{"name", p.joint->name}, {"type", joint_type_name(p.joint->type)}};
      parts.push_back(std::move(pj));
    }
    dj["parts"] = std::move(parts);
    dj["tool"] = device->tool_part < 0 ? nullptr : nlohmann::ordered_json(device->parts[device->tool_part].name);
    dj["driven"] = device->kinematic ? "kinematic" : "motors";
    dj["urdf"] = device->urdf.empty() ? nullptr : nlohmann::ordered_json(device->urdf);
    dj["srdf"] = device->srdf.empty() ? nullptr : nlohmann::ordered_json(device->srdf);
    if (!device->urdf.empty()) dj["joint_limits"] = device->hard_limits ? "hard" : "soft";
    auto allowed = nlohmann::ordered_json::array();
    for (const auto& [a, b] : device->allowed_names) allowed.push_back({a, b});
    dj["allowed_collisions"] = std::move(allowed);
    auto joints = nlohmann::ordered_json::array();
    for (const TypeInstance::JointMotion& m : instance.joints) {
      const bool turns = m.type == JointType::Revolute;
      const Dim dim = turns ? Dim::Angle : Dim::Length;
      joints.push_back({{"name", m.name},
                        {"type", joint_type_name(m.type)},
                        {"speed", stable(si_to_file(m.speed, dim))},
                        {"speed_unit", turns ? "deg/s" : "m/s"},
                        {"acceleration", stable(si_to_file(m.acceleration, dim))},
                        {"acceleration_unit", turns ? "deg/s^2" : "m/s^2"},
                        {"speed_given", m.speed_given},
                        {"acceleration_given", m.acceleration_given}});
    }
    dj["joints"] = std::move(joints);
    dj["reach"] = instance.reach ? nlohmann::ordered_json{{"min", vec_json(instance.reach->min())}, {"max", vec_json(instance.reach->max())}}
                                 : nlohmann::ordered_json(nullptr);
    j["device"] = std::move(dj);
  }
  return j;
}

}  // namespace

void write_type_listing(std::ostream& out, std::vector<ObjectType> types, const PluginSet& plugins, const CompileOptions& instance_options,
                        bool json, Sources& sources, Diagnostics& problems) {
  // One instance of each type at its defaults shows where its frames, bounds and reach are.
  auto library = std::make_shared<const std::vector<ObjectType>>(types);
  std::map<std::string, TypeInstance> instances;
  Diagnostics found;
  for (const ObjectType& t : *library) instances[t.name] = instance_at_defaults(library, t, instance_options, sources, found);
  // A base type's problem meets every type extending it: report it once.
  std::set<std::tuple<uint32_t, uint32_t, uint32_t, std::string>> seen;
  for (const Diagnostic& d : found.warnings()) problems.warning(d.mark, d.message);
  for (const Diagnostic& d : found.errors())
    if (seen.insert({d.mark.file, d.mark.line, d.mark.column, d.message}).second) problems.error(d.mark, d.message);
  std::sort(types.begin(), types.end(), [](const ObjectType& a, const ObjectType& b) { return a.name < b.name; });
  // Sorting moved them: base indices refer to the old order, so look bases up by name below.
  std::map<std::string, std::string> base_of;
  for (const ObjectType& t : types) base_of[t.name] = t.extends.empty() ? "object" : t.extends;
  if (json) {
    nlohmann::ordered_json j;
    j["sscs"] = 1;
    auto arr = nlohmann::ordered_json::array();
    for (const ObjectType& t : types) {
      auto tj = type_json(t, types, t.templates.device.get(), instances[t.name]);
      tj["extends"] = base_of[t.name];
      arr.push_back(std::move(tj));
    }
    j["types"] = std::move(arr);
    j["constraint_kinds"] = kConstraintKindNames;
    auto classes = nlohmann::ordered_json::array();
    for (const ConstraintClass& c : plugins.classes())
      classes.push_back({{"class", c.name}, {"description", c.description}, {"plugin", c.plugin},
                         {"min_attributes", c.min_values},
                         {"max_attributes", c.max_values == SIZE_MAX ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(c.max_values)}});
    j["constraint_classes"] = std::move(classes);
    out << j.dump(2) << "\n";
    return;
  }
  for (const ObjectType& t : types) {
    out << fmt::format("{} ({}{}{}){}\n", t.name, t.device ? "device, " : "", "extends " + base_of[t.name],
                             t.plugin.empty() ? "" : "; plugin " + t.plugin,
                             t.description.empty() ? "" : " - " + t.description);
    size_t name_width = 16;  // the names' column fits the longest (finger_right_joint)
    for (const AttributeDef& a : t.attributes) name_width = std::max(name_width, a.name.size());
    for (const AttributeDef& a : t.attributes) {
      const char* unit = file_unit(a.dim);
      std::string range;
      if (a.min_si || a.max_si || a.min_expr.present || a.max_expr.present)
        range = fmt::format("  [{}, {}]", a.min_si ? number_text(si_to_file(*a.min_si, a.dim)) : a.min_expr.text,
                            a.max_si ? number_text(si_to_file(*a.max_si, a.dim)) : a.max_expr.text);
      std::string values = a.type == AttrType::Enum ? fmt::format("  {{{}}}", fmt::join(a.values, ", ")) : "";
      // A joint's default is its home, in the unit of the column (the type may write it in rad).
      std::string def = a.joint ? fmt::format("  default {}", number_text(si_to_file(a.home_si, a.dim)))
                        : a.default_value.present ? fmt::format("  default {}", a.default_value.text)
                                                  : "  required";
      out << fmt::format("  {:<{}} {:<8} {:<4}{}{}{}{}\n", a.name, name_width, a.joint ? "joint" : attr_type_name(a.type), unit,
                               def, range, values, a.description.empty() ? "" : "  # " + a.description);
    }
    const TypeInstance& in = instances[t.name];
    if (!in.unbuilt.empty()) {
      out << fmt::format("  at its defaults: no instance ({})\n", in.unbuilt);
    } else {
      std::vector<std::string> frames;
      for (const auto& [name, X] : in.frames) {
        auto rpy = frame_rpy_deg(X);
        frames.push_back(fmt::format("{} {}{}", name, vec_text(X.translation()), rpy ? " rpy " + vec_text(*rpy) : ""));
      }
      out << fmt::format("  frames at the defaults (m, deg, in the type's frame): {}\n", fmt::join(frames, "; "));
      if (!in.bounds.isEmpty())
        out << fmt::format("  bounds at the defaults: {} to {} m\n", vec_text(in.bounds.min()), vec_text(in.bounds.max()));
      std::vector<std::string> meshes;
      for (const TypeInstance::Mesh& m : in.meshes) meshes.push_back(fmt::format("{} ({})", m.file, m.closed ? "closed: a solid" : "open: a surface"));
      if (!meshes.empty()) out << fmt::format("  meshes: {}\n", fmt::join(meshes, ", "));
      if (in.reach)
        out << fmt::format("  tool reach over the joint ranges: {} to {} m\n", vec_text(in.reach->min()), vec_text(in.reach->max()));
      std::vector<std::string> motion;
      for (const TypeInstance::JointMotion& m : in.joints) {
        const bool turns = m.type == JointType::Revolute;
        const Dim dim = turns ? Dim::Angle : Dim::Length;
        motion.push_back(fmt::format("{} {} {}, {} {}{}", m.name, number_text(si_to_file(m.speed, dim)), turns ? "deg/s" : "m/s",
                                     number_text(si_to_file(m.acceleration, dim)), turns ? "deg/s²" : "m/s²",
                                     m.speed_given && m.acceleration_given ? "" : " (defaults)"));
      }
      if (!motion.empty()) out << fmt::format("  joint speeds and accelerations: {}\n", fmt::join(motion, "; "));
    }
    if (const DeviceTemplate* d = t.templates.device.get()) {
      std::vector<std::string> parts;
      for (const PartTemplate& p : d->parts)
        parts.push_back(p.joint && p.joint->type != JointType::Fixed ? fmt::format("{}({})", p.name, p.joint->name) : p.name);
      out << fmt::format("  parts: {}; tool: {}{}{}{}\n", fmt::join(parts, ", "),
                               d->tool_part < 0 ? "(end of the longest chain)" : d->parts[d->tool_part].name,
                               d->kinematic ? "; driven: kinematic" : "",
                               !d->urdf.empty() ? fmt::format("; urdf: {} ({} limits)", d->urdf, d->hard_limits ? "hard" : "soft") : "",
                               !d->srdf.empty() ? "; srdf: " + d->srdf : "");
      if (!d->allowed_names.empty()) {
        std::vector<std::string> pairs;
        for (const auto& [a, b] : d->allowed_names) pairs.push_back(a + "/" + b);
        out << fmt::format("  allowed collisions: {}\n", fmt::join(pairs, ", "));
      }
    }
  }
  out << fmt::format("constraint kinds: {}\n", fmt::join(kConstraintKindNames, ", "));
  for (const ConstraintClass& c : plugins.classes())
    out << fmt::format("plugin constraint class {} - {} ({} attributes; {})\n", c.name, c.description,
                             c.min_values == c.max_values ? fmt::format("{}", c.min_values)
                             : c.max_values == SIZE_MAX  ? fmt::format("{} or more", c.min_values)
                                                         : fmt::format("{} to {}", c.min_values, c.max_values),
                             c.plugin);
}

}  // namespace sscs
