#include <filesystem>
#include <algorithm>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>

#include "core/digest.h"
#include "core/names.h"
#include "core/units.h"
#include "load/load.h"

#include "core/files.h"
#include "core/limits.h"
#include "load/reader.h"

namespace fs = std::filesystem;

namespace sscs {

bool missing_reference(const std::string& what, const std::string& type_file, const std::string& rel, SourceMark where,
                       Diagnostics& diag) {
  std::error_code ec;
  const std::string path = resolve_mesh_path(type_file, rel);
  if (fs::exists(path, ec) || fs::is_symlink(path, ec)) return false;
  if (fs::path(rel).is_absolute()) {
    diag.error(where, fmt::format("{} '{}' does not exist", what, rel));
  } else {
    const fs::path folder = fs::path(type_file).parent_path();
    diag.error(where, fmt::format("{} '{}' does not exist (looked for {}, from the type file's folder, and {}, from its library folder)", what,
                                  rel, join_path(folder.string(), rel), join_path(folder.parent_path().string(), rel)));
  }
  return true;
}

uint32_t read_source(const std::string& path, Sources& sources, Diagnostics& diag, SourceMark where) {
  const uintmax_t limit = limit_bytes("SSCS_MAX_FILE_MB", kMaxInputFileMb);
  auto too_big = [&](uintmax_t size) {
    diag.error(where, fmt::format("cannot read '{}': it is {:.0f} MB, above the {:.0f} MB limit of an input file "
                                  "(raise it with SSCS_MAX_FILE_MB)", path, size / 1e6, limit / 1e6));
    return uint32_t{0};
  };
  if (const std::string* text = sources.unsaved(path)) {  // an editor's buffer, saved or not
    if (std::string why = where.valid() ? outside_roots(path) : ""; !why.empty()) {
      diag.error(where, fmt::format("cannot read '{}': it {}", path, why));
      return 0;
    }
    if (text->size() > limit) return too_big(text->size());
    return sources.add(path, *text);
  }
  // A file named in another (where is valid) stays inside the project; a FIFO would be read for ever.
  if (std::string why = where.valid() ? not_a_readable_reference(path) : not_a_file(path); !why.empty()) {
    diag.error(where, fmt::format("cannot read '{}': it {}", path, why));
    return 0;
  }
  std::error_code ec;
  const uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > limit) return too_big(size);
  errno = 0;
  std::optional<std::string> text = read_file_bytes(path);
  if (!text) {
    diag.error(where, fmt::format("cannot read '{}': {}", path, errno ? std::strerror(errno) : "read error"));
    return 0;
  }
  return sources.add(path, std::move(*text));
}

namespace load {

MapReader::MapReader(yaml::Node node, std::string what, Diagnostics& diag)
    : node_(node), what_(std::move(what)), diag_(diag) {
  known_.reserve(16);
  if (!node.valid()) return;
  if (!node.is_map()) {
    expected(diag, node, "a mapping", what_);
    return;
  }
  ok_ = true;
}

yaml::Node MapReader::take(std::string_view key) {
  known_.emplace_back(key);
  return ok_ ? node_.find(key) : yaml::Node();
}

yaml::Node MapReader::require(std::string_view key) {
  yaml::Node n = take(key);
  if (!ok_ || n.valid()) return n;
  // A key written misspelt (`devcies`): that one error, said where it is, not also "missing
  // 'devices'" (a follow-on error); it is then known, so finish() does not say it again.
  for (size_t i = 0; i < node_.size(); ++i) {
    const std::string_view k = node_.key(i).text();
    if (std::find(known_.begin(), known_.end(), k) != known_.end()) continue;
    if (closest_name(k, {std::string(key)}) == key) {
      diag_.error(node_.key(i).mark(), fmt::format("unknown key '{}' in {} (did you mean '{}'?)", k, what_, key));
      known_.emplace_back(k);
      return n;
    }
  }
  diag_.error(node_.mark(), fmt::format("{} is missing the required key '{}'", what_, key));
  return n;
}

std::vector<std::pair<yaml::Node, yaml::Node>> MapReader::rest() {
  std::vector<std::pair<yaml::Node, yaml::Node>> out;
  if (!ok_) return out;
  for (size_t i = 0; i < node_.size(); ++i) {
    std::string_view k = node_.key(i).text();
    if (std::find(known_.begin(), known_.end(), k) == known_.end()) out.emplace_back(node_.key(i), node_.value(i));
  }
  return out;
}

void MapReader::finish() {
  for (auto& [key, value] : rest()) {
    diag_.error(key.mark(), fmt::format("unknown key '{}' in {}{}", key.text(), what_,
                                        did_you_mean(key.text(), std::vector<std::string>(known_.begin(), known_.end()))));
  }
}

void expected(Diagnostics& diag, yaml::Node node, std::string_view expectation, std::string_view what) {
  diag.error(node.mark(), fmt::format("expected {} for {}, found {}", expectation, what, node.describe()));
}

Scalar scalar(yaml::Node node, std::string_view what, Diagnostics& diag) {
  Scalar s;
  if (!node.valid()) return s;
  s.present = true;
  s.mark = node.mark();
  if (node.is_null()) {
    s.null = true;
    return s;
  }
  if (!node.is_scalar()) {
    expected(diag, node, "a value", what);
    s.null = true;
    return s;
  }
  s.text = std::string(node.text());
  s.quoted = node.quoted();
  if (std::string why = s.quoted ? "" : nonfinite_number(s.text); !why.empty())
    diag.error(s.mark, fmt::format("expected a finite number for {}, found '{}': {}", what, s.text, why));
  return s;
}

std::string text(yaml::Node node, std::string_view what, Diagnostics& diag) {
  if (!node.valid()) return {};
  if (!node.is_scalar()) {
    expected(diag, node, "a string", what);
    return {};
  }
  return std::string(node.text());
}

std::string name(yaml::Node node, std::string_view what, Diagnostics& diag) {
  if (!node.valid()) return {};
  if (!node.is_scalar()) {
    expected(diag, node, "a name", what);
    return {};
  }
  std::string n(node.text());
  if (!is_valid_name(n)) {
    diag.error(node.mark(), fmt::format("expected a name for {} (a letter, then letters, digits, '_' or '-'), found '{}'",
                                        what, n));
    return {};
  }
  return n;
}

bool boolean(yaml::Node node, std::string_view what, Diagnostics& diag, bool fallback) {
  if (!node.valid()) return fallback;
  if (node.is_scalar() && !node.quoted()) {
    if (node.text() == "true") return true;
    if (node.text() == "false") return false;
  }
  expected(diag, node, "true or false", what);
  return fallback;
}

std::array<Scalar, 3> vec3(yaml::Node node, std::string_view what, Diagnostics& diag) {
  std::array<Scalar, 3> v;
  if (!node.valid()) return v;
  if (!node.is_sequence() || node.size() != 3) {
    expected(diag, node, "a sequence of three values [x, y, z]", what);
    return v;
  }
  for (size_t i = 0; i < 3; ++i) v[i] = scalar(node.item(i), what, diag);
  return v;
}

PoseSpec pose(MapReader& reader, Diagnostics& diag) {
  PoseSpec p;
  p.xyz = vec3(reader.take("xyz"), "xyz", diag);
  p.rpy = vec3(reader.take("rpy"), "rpy", diag);
  return p;
}

std::optional<RepeatSpec> repeat(MapReader& reader, Diagnostics& diag) {
  yaml::Node node = reader.take("repeat");
  if (!node.valid()) return std::nullopt;
  RepeatSpec out;
  out.mark = node.mark();
  if (!node.is_map() || node.size() == 0) {
    expected(diag, node, "a map of counters {name: count} or {name: {count, pitch}}", "repeat");
    return out;
  }
  for (size_t i = 0; i < node.size(); ++i) {
    RepeatSpec::Counter c;
    c.name = name(node.key(i), "a repeat counter", diag);
    c.mark = node.key(i).mark();
    yaml::Node value = node.value(i);
    if (value.is_map()) {
      MapReader r(value, fmt::format("repeat counter '{}'", c.name), diag);
      c.count = scalar(r.require("count"), "a repeat count", diag);
      c.pitch = vec3(r.take("pitch"), "a repeat pitch", diag);
      r.finish();
    } else {
      c.count = scalar(value, "a repeat count", diag);
    }
    for (const RepeatSpec::Counter& other : out.counters)
      if (other.name == c.name) diag.error(c.mark, fmt::format("repeat counter '{}' is named twice", c.name));
    out.counters.push_back(std::move(c));
  }
  return out;
}

std::vector<Scalar> scalar_list(yaml::Node node, std::string_view what, Diagnostics& diag) {
  std::vector<Scalar> out;
  if (!node.valid()) return out;
  if (node.is_sequence()) {
    for (size_t i = 0; i < node.size(); ++i) out.push_back(scalar(node.item(i), what, diag));
  } else {
    out.push_back(scalar(node, what, diag));
  }
  return out;
}

std::vector<GeometrySpec> geometry_list(yaml::Node node, Diagnostics& diag) {
  std::vector<GeometrySpec> out;
  if (!node.valid()) return out;
  if (!node.is_sequence()) {
    expected(diag, node, "a sequence of shapes (box, cylinder, sphere, mesh)", "geometry");
    return out;
  }
  static const std::vector<std::string> kShapes = {"box", "cylinder", "sphere", "mesh"};
  for (size_t i = 0; i < node.size(); ++i) {
    yaml::Node item = node.item(i);
    if (!item.is_map() || item.size() != 1) {
      expected(diag, item, "one shape: {box: ...}, {cylinder: ...}, {sphere: ...} or {mesh: ...}", "geometry");
      continue;
    }
    std::string_view shape = item.key(0).text();
    GeometrySpec g;
    g.mark = item.mark();
    MapReader r(item.value(0), fmt::format("{} geometry", shape), diag);
    if (shape == "box") {
      g.shape = BoxSpec{vec3(r.require("size"), "box size", diag)};
    } else if (shape == "cylinder") {
      g.shape = CylinderSpec{scalar(r.require("radius"), "cylinder radius", diag),
                             scalar(r.require("length"), "cylinder length", diag)};
    } else if (shape == "sphere") {
      g.shape = SphereSpec{scalar(r.require("radius"), "sphere radius", diag)};
    } else if (shape == "mesh") {
      MeshSpec m;
      m.file = scalar(r.require("file"), "mesh file", diag);
      m.scale = vec3(r.take("scale"), "mesh scale", diag);
      g.shape = std::move(m);
    } else {
      diag.error(item.key(0).mark(), fmt::format("unknown shape '{}'; expected box, cylinder, sphere or mesh{}", shape,
                                                 did_you_mean(shape, kShapes)));
      continue;
    }
    g.pose = pose(r, diag);
    g.repeat = repeat(r, diag);
    r.finish();
    out.push_back(std::move(g));
  }
  return out;
}

void check_version(MapReader& root, Diagnostics& diag) {
  yaml::Node v = root.require("sscs");
  if (v.valid() && !(v.is_scalar() && !v.quoted() && v.text() == "1"))
    expected(diag, v, "format version 1", "sscs");
}

nlohmann::ordered_json to_json(yaml::Node node) {
  switch (node.kind()) {
    case yaml::Kind::Null: return nullptr;
    case yaml::Kind::Scalar: {
      if (!node.quoted()) {
        if (node.text() == "true") return true;
        if (node.text() == "false") return false;
        if (auto n = parse_number(node.text())) return *n;
      }
      return std::string(node.text());
    }
    case yaml::Kind::Sequence: {
      auto arr = nlohmann::ordered_json::array();
      for (size_t i = 0; i < node.size(); ++i) arr.push_back(to_json(node.item(i)));
      return arr;
    }
    case yaml::Kind::Map: {
      auto obj = nlohmann::ordered_json::object();
      for (size_t i = 0; i < node.size(); ++i) obj[std::string(node.key(i).text())] = to_json(node.value(i));
      return obj;
    }
  }
  return nullptr;
}

CameraKeySpec read_camera(yaml::Node node, Diagnostics& diag, bool keyframe) {
  CameraKeySpec c;
  c.mark = node.mark();
  MapReader r(node, keyframe ? "camera keyframe" : "camera", diag);
  if (!r.ok()) return c;
  if (keyframe) c.t = load::scalar(r.require("t"), "camera time", diag);
  c.fov = load::scalar(r.take("fov"), "fov", diag);
  yaml::Node orbit = r.take("orbit");
  yaml::Node eye = r.take("eye");
  yaml::Node target = r.take("target");
  if (orbit.valid()) {
    c.orbit = true;
    if (eye.valid() || target.valid())
      diag.error(orbit.mark(), fmt::format("{} has either 'orbit' or 'eye' and 'target', not both",
                                           keyframe ? "a camera keyframe" : "a camera"));
    MapReader o(orbit, "orbit", diag);
    yaml::Node ot = o.require("target");
    if (ot.is_sequence()) c.orbit_point = load::vec3(ot, "orbit target", diag);
    else c.orbit_target = load::scalar(ot, "orbit target", diag);
    c.radius = load::scalar(o.require("radius"), "orbit radius", diag);
    c.azimuth = load::scalar(o.take("azimuth"), "orbit azimuth", diag);
    c.elevation = load::scalar(o.take("elevation"), "orbit elevation", diag);
    if (o.ok()) o.finish();
  } else {
    if (!eye.valid() || !target.valid())
      diag.error(c.mark, fmt::format("{} needs 'eye' and 'target' (or 'orbit')", keyframe ? "a camera keyframe" : "a camera"));
    c.eye = load::vec3(eye, "camera eye", diag);
    c.target = load::vec3(target, "camera target", diag);
  }
  r.finish();
  return c;
}

}  // namespace load
}  // namespace sscs
