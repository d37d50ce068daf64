// Type-library files: `sscs: 1`, `type: NAME`, attributes, frames, geometry, devices.
#include <algorithm>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/names.h"
#include "core/yaml_tree.h"
#include "load/load.h"
#include "load/reader.h"

namespace sscs {

using load::MapReader;

namespace {

AttributeDecl read_attribute(yaml::Node key, yaml::Node value, Diagnostics& diag) {
  AttributeDecl a;
  a.name = load::name(key, "an attribute", diag);
  a.mark = key.mark();
  if (is_object_key(a.name))
    diag.error(a.mark, fmt::format("an attribute may not be named '{}', a key of every object (an object could not set it)", a.name));
  static const std::vector<std::string> kTypes = {"length", "angle",   "mass",   "time", "number",
                                                  "integer", "boolean", "string", "enum"};
  MapReader r(value, fmt::format("attribute '{}'", a.name), diag);
  yaml::Node type = r.require("type");
  if (type.valid()) {
    std::string word = load::text(type, "an attribute type", diag);
    if (auto t = attr_type_from(word)) {
      a.type = *t;
    } else if (type.is_scalar()) {
      diag.error(type.mark(), fmt::format("expected an attribute type ({}), found '{}'{}", fmt::join(kTypes, ", "), word,
                                          did_you_mean(word, kTypes)));
    }
  }
  a.default_value = load::scalar(r.take("default"), "default", diag);
  a.min = load::scalar(r.take("min"), "min", diag);
  a.max = load::scalar(r.take("max"), "max", diag);
  a.description = load::text(r.take("description"), "description", diag);
  yaml::Node values = r.take("values");
  if (values.valid()) {
    if (a.type != AttrType::Enum) diag.error(values.mark(), "'values' is only allowed for enum attributes");
    if (!values.is_sequence() || values.size() == 0) {
      load::expected(diag, values, "a non-empty sequence of names", "enum values");
    } else {
      for (size_t i = 0; i < values.size(); ++i) a.values.push_back(load::name(values.item(i), "an enum value", diag));
    }
  } else if (a.type == AttrType::Enum) {
    diag.error(r.mark(), fmt::format("enum attribute '{}' needs 'values'", a.name));
  }
  r.finish();
  return a;
}

/// A repeated frame's name holds each of its counters once, in braces (`slot_{level}_{bay}`),
/// and reads as a name with numbers in their places; a frame that is not repeated has none.
void check_frame_name(const FrameSpec& f, Diagnostics& diag) {
  if (f.name.empty()) return;
  std::string filled;
  std::vector<std::string> used;
  for (size_t i = 0; i < f.name.size(); ++i) {
    if (f.name[i] == '}') {
      diag.error(f.mark, fmt::format("frame name '{}' has a '}}' without its '{{'", f.name));
      return;
    }
    if (f.name[i] != '{') {
      filled += f.name[i];
      continue;
    }
    size_t end = f.name.find('}', i);
    if (end == std::string::npos) {
      diag.error(f.mark, fmt::format("frame name '{}' has a '{{' without its '}}'", f.name));
      return;
    }
    used.push_back(f.name.substr(i + 1, end - i - 1));
    filled += "1";
    i = end;
  }
  if (!is_valid_name(filled)) {
    diag.error(f.mark, fmt::format("expected a name for a frame (a letter, then letters, digits, '_' or '-', with {{counter}} "
                                   "standing for a number in a repeated frame), found '{}'", f.name));
    return;
  }
  std::vector<std::string> counters;
  if (f.repeat)
    for (const RepeatSpec::Counter& c : f.repeat->counters) counters.push_back(c.name);
  for (const std::string& u : used)
    if (std::find(counters.begin(), counters.end(), u) == counters.end())
      diag.error(f.mark, counters.empty() ? fmt::format("frame name '{}' names '{{{}}}', but the frame has no 'repeat'", f.name, u)
                                          : fmt::format("frame name '{}' names '{{{}}}', which is not a counter of its repeat ({}){}",
                                                        f.name, u, fmt::join(counters, ", "), did_you_mean(u, counters)));
  for (const std::string& c : counters)
    if (std::count(used.begin(), used.end(), c) != 1)
      diag.error(f.mark, fmt::format("frame name '{}' must name counter '{}' once, as {{{}}}, so that each copy has a name of its own",
                                     f.name, c, c));
}

JointSpec read_joint(yaml::Node node, Diagnostics& diag) {
  JointSpec j;
  MapReader r(node, "joint", diag);
  j.mark = node.mark();
  j.name = load::name(r.require("name"), "a joint", diag);
  yaml::Node type = r.require("type");
  std::string word = load::text(type, "joint type", diag);
  if (word == "revolute") j.type = JointType::Revolute;
  else if (word == "prismatic") j.type = JointType::Prismatic;
  else if (word == "fixed") j.type = JointType::Fixed;
  else if (type.valid()) load::expected(diag, type, "revolute, prismatic or fixed", "joint type");
  j.axis = load::vec3(r.take("axis"), "joint axis", diag);
  if (j.type != JointType::Fixed && !j.axis[0].present) diag.error(j.mark, fmt::format("joint '{}' needs an 'axis'", j.name));
  j.origin = load::pose(r, diag);
  MapReader limits(r.take("limits"), "joint limits", diag);
  j.min = load::scalar(limits.take("min"), "joint min", diag);
  j.max = load::scalar(limits.take("max"), "joint max", diag);
  j.velocity = load::scalar(limits.take("velocity"), "joint velocity", diag);
  j.acceleration = load::scalar(limits.take("acceleration"), "joint acceleration", diag);
  j.effort = load::scalar(limits.take("effort"), "joint effort", diag);
  if (limits.ok()) limits.finish();
  r.finish();
  return j;
}

DeviceSpec read_device(MapReader& root, Diagnostics& diag) {
  DeviceSpec d;
  yaml::Node parts = root.take("parts");
  d.urdf = load::scalar(root.take("urdf"), "urdf", diag);
  if (parts.valid() && d.urdf.present) diag.error(d.urdf.mark, "a device has either 'parts' or 'urdf', not both");
  if (!parts.valid() && !d.urdf.present) diag.error(root.mark(), "a device needs 'parts' (or 'urdf')");
  if (parts.valid() && (!parts.is_sequence() || parts.size() == 0))
    load::expected(diag, parts, "a non-empty sequence of parts", "parts");
  else if (parts.valid())
    for (size_t i = 0; i < parts.size(); ++i) {
      MapReader p(parts.item(i), "part", diag);
      if (!p.ok()) continue;
      PartSpec part;
      part.mark = p.mark();
      part.name = load::name(p.require("name"), "a part", diag);
      yaml::Node parent = p.take("parent");
      part.parent = load::name(parent, "a parent part", diag);
      if (parent.valid()) part.parent_mark = parent.mark();
      yaml::Node joint = p.take("joint");
      if (joint.valid()) part.joint = read_joint(joint, diag);
      if (joint.valid() && !parent.valid()) diag.error(joint.mark(), "the root part has no parent, so it has no joint");
      if (!joint.valid() && parent.valid())
        diag.error(part.mark, fmt::format("part '{}' has a parent but no joint (use type: fixed)", part.name));
      part.geometry = load::geometry_list(p.take("geometry"), diag);
      part.mass = load::scalar(p.take("mass"), "part mass", diag);
      part.color = load::scalar(p.take("color"), "part color", diag);
      p.finish();
      d.parts.push_back(std::move(part));
    }
  yaml::Node tool = root.take("tool");
  if (tool.valid()) {
    MapReader t(tool, "tool", diag);
    yaml::Node part = t.require("part");
    d.tool_part = load::name(part, "the tool part", diag);
    d.tool_mark = part.valid() ? part.mark() : tool.mark();
    d.tool_pose = load::pose(t, diag);
    t.finish();
  }
  yaml::Node home = root.take("home");
  if (home.valid()) {
    d.home_mark = home.mark();
    MapReader h(home, "home", diag);
    for (auto& [k, v] : h.rest()) d.home.emplace_back(load::name(k, "a joint", diag), load::scalar(v, "home value", diag));
  }
  yaml::Node driven = root.take("driven");
  if (driven.valid()) {
    std::string word = load::text(driven, "driven", diag);
    if (word == "kinematic") d.kinematic = true;
    else if (word != "motors") load::expected(diag, driven, "motors or kinematic", "driven");
  }
  yaml::Node limits = root.take("joint_limits");
  if (limits.valid()) {
    std::string word = load::text(limits, "joint_limits", diag);
    if (word == "hard") d.hard_limits = true;
    else if (word != "soft") load::expected(diag, limits, "soft or hard", "joint_limits");
    if (!d.urdf.present) diag.error(limits.mark(), "'joint_limits' chooses between a URDF's soft and hard limits: it needs 'urdf'");
  }
  yaml::Node allowed = root.take("allowed_collisions");
  if (allowed.valid() && !allowed.is_sequence()) load::expected(diag, allowed, "a sequence of part pairs [a, b]", "allowed_collisions");
  else if (allowed.valid())
    for (size_t i = 0; i < allowed.size(); ++i) {
      yaml::Node pair = allowed.item(i);
      if (!pair.is_sequence() || pair.size() != 2) {
        load::expected(diag, pair, "a pair of part names [a, b]", "allowed_collisions");
        continue;
      }
      d.allowed_collisions.push_back({load::name(pair.item(0), "a part", diag), load::name(pair.item(1), "a part", diag), pair.mark()});
    }
  d.srdf = load::scalar(root.take("srdf"), "srdf", diag);
  if (d.srdf.present && !d.urdf.present) diag.error(d.srdf.mark, "an SRDF describes a URDF robot: 'srdf' needs 'urdf'");
  return d;
}

}  // namespace

std::optional<TypeSpec> load_type(const std::string& path, Sources& sources, Diagnostics& diag, SourceMark where,
                                  const std::vector<std::string>& package_paths) {
  uint32_t file = read_source(path, sources, diag, where);
  if (file == 0) return std::nullopt;
  return load_type(file, path, sources, diag, package_paths);
}

std::optional<TypeSpec> load_type(uint32_t file, const std::string& path, Sources& sources, Diagnostics& diag,
                                  const std::vector<std::string>& package_paths) {
  yaml::Document doc = yaml::parse(sources, file, diag);
  if (doc.empty()) return std::nullopt;
  MapReader root(doc.root(), "a type file", diag);
  if (!root.ok()) return std::nullopt;
  load::check_version(root, diag);
  TypeSpec t;
  t.path = path;
  yaml::Node type = root.require("type");
  t.name = load::name(type, "the type", diag);
  t.mark = type.valid() ? type.mark() : root.mark();
  yaml::Node extends = root.take("extends");
  t.extends = load::name(extends, "extends", diag);
  t.extends_mark = extends.valid() ? extends.mark() : t.mark;
  if (t.extends == "object") t.extends.clear();
  t.description = load::text(root.take("description"), "description", diag);
  yaml::Node kind = root.take("kind");
  bool device = false;
  if (kind.valid()) {
    std::string word = load::text(kind, "kind", diag);
    if (word == "device") device = true;
    else if (word != "object") load::expected(diag, kind, "object or device", "kind");
  }
  MapReader attrs(root.take("attributes"), "attributes", diag);
  for (auto& [k, v] : attrs.rest()) t.attributes.push_back(read_attribute(k, v, diag));
  MapReader frames(root.take("frames"), "frames", diag);
  for (auto& [k, v] : frames.rest()) {
    FrameSpec f;
    const bool pattern = k.is_scalar() && k.text().find_first_of("{}") != std::string_view::npos;
    f.name = pattern ? std::string(k.text()) : load::name(k, "a frame", diag);
    f.mark = k.mark();
    MapReader fr(v, fmt::format("frame '{}'", f.name), diag);
    f.pose = load::pose(fr, diag);
    f.repeat = load::repeat(fr, diag);
    fr.finish();
    check_frame_name(f, diag);
    t.frames.push_back(std::move(f));
  }
  yaml::Node geometry = root.take("geometry");
  t.has_geometry = geometry.valid();
  t.geometry = load::geometry_list(geometry, diag);
  t.color = load::scalar(root.take("color"), "color", diag);
  t.container = load::boolean(root.take("container"), "container", diag);
  t.zone = load::boolean(root.take("zone"), "zone", diag);
  if (t.zone && (device || t.container))
    diag.error(t.mark, fmt::format("a zone is a keep-out volume: '{}' cannot also be a {}", t.name, device ? "device" : "container"));
  yaml::Node rules = root.take("requires");
  if (rules.valid() && !rules.is_sequence()) load::expected(diag, rules, "a sequence of {condition, message}", "requires");
  else if (rules.valid())
    for (size_t i = 0; i < rules.size(); ++i) {
      MapReader r(rules.item(i), "a rule of requires", diag);
      if (!r.ok()) continue;
      RuleSpec rule;
      rule.mark = r.mark();
      rule.condition = load::scalar(r.require("condition"), "a rule's condition", diag);
      rule.message = load::text(r.require("message"), "a rule's message", diag);
      r.finish();
      t.rules.push_back(std::move(rule));
    }
  if (t.container && device) diag.error(t.mark, "a device is no container: 'container' is for objects that hold others");
  if (yaml::Node mass = root.take("mass"); mass.valid()) {
    if (device) diag.error(mass.mark(), "a device's mass is its parts' masses; 'mass' is for objects that are not devices");
    else t.mass = load::scalar(mass, "mass", diag);
  }
  if (device) {
    t.device = read_device(root, diag);
    if (t.device->urdf.present && !t.device->urdf.null) load_urdf(*t.device, path, package_paths, sources);
    if (t.device->srdf.present && !t.device->srdf.null) load_srdf(*t.device, path, sources);
  } else {
    static const char* kDeviceKeys[] = {"parts", "tool", "home", "driven", "urdf", "srdf", "joint_limits", "allowed_collisions"};
    for (const char* key : kDeviceKeys)
      if (root.has(key)) diag.error(root.node().find(key).mark(), fmt::format("'{}' is only allowed with kind: device", key));
    for (const char* key : kDeviceKeys) root.take(key);
  }
  root.finish();
  return t;
}

}  // namespace sscs
