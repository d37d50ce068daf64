// Vault files: `sscs: 1`, `vault: NAME`, parameters, objects, constraints.
#include <fmt/format.h>

#include "core/names.h"
#include "core/timer.h"
#include "core/yaml_tree.h"
#include "load/load.h"
#include "load/reader.h"

namespace sscs {

using load::MapReader;

namespace {

ParameterSpec read_parameter(yaml::Node key, yaml::Node value, Diagnostics& diag) {
  ParameterSpec p;
  p.name = load::name(key, "a parameter", diag);
  p.mark = key.mark();
  if (value.is_map()) {
    MapReader r(value, fmt::format("parameter '{}'", p.name), diag);
    p.value = load::scalar(r.require("value"), "parameter value", diag);
    yaml::Node type = r.take("type");
    if (type.valid()) {
      std::string word = load::text(type, "parameter type", diag);
      p.type = attr_type_from(word);
      if (!p.type && type.is_scalar()) load::expected(diag, type, "an attribute type", "parameter type");
      if (p.type == AttrType::Enum || p.type == AttrType::String)
        diag.error(type.mark(), "parameters are numeric: use length, angle, mass, time, number, integer or boolean");
    }
    p.min = load::scalar(r.take("min"), "min", diag);
    p.max = load::scalar(r.take("max"), "max", diag);
    r.finish();
  } else {
    p.value = load::scalar(value, "parameter value", diag);
  }
  if (p.value.present && p.value.null) diag.error(p.value.mark, fmt::format("parameter '{}' has no value", p.name));
  return p;
}

ObjectSpec read_object(yaml::Node node, Diagnostics& diag) {
  ObjectSpec o;
  MapReader r(node, "object", diag);
  o.mark = node.mark();
  if (!r.ok()) return o;
  yaml::Node type = r.require("type");
  o.type = load::name(type, "the object type", diag);
  o.type_mark = type.valid() ? type.mark() : o.mark;
  yaml::Node array = r.take("array");
  yaml::Node name = r.take("name");
  if (array.valid()) {
    if (name.valid()) diag.error(name.mark(), "an object with 'array' takes its names from array.name, not 'name'");
    MapReader a(array, "array", diag);
    ArraySpec spec;
    spec.mark = array.mark();
    spec.name_pattern = load::scalar(a.require("name"), "array name", diag);
    yaml::Node count = a.require("count");
    spec.count = load::scalar_list(count, "array count", diag);
    if (count.valid() && (spec.count.empty() || spec.count.size() > 3))
      load::expected(diag, count, "one to three counts", "array count");
    yaml::Node pitch = a.take("pitch");
    if (pitch.valid() && pitch.is_sequence() && pitch.size() >= 1 && pitch.size() <= 3) {
      for (size_t i = 0; i < pitch.size(); ++i) spec.pitch[i] = load::scalar(pitch.item(i), "array pitch", diag);
    } else if (pitch.valid()) {
      load::expected(diag, pitch, "a sequence of one to three steps [x, y, z]", "array pitch");
    }
    yaml::Node skip = a.take("skip");
    if (skip.valid() && !skip.is_sequence()) load::expected(diag, skip, "a list of index tuples [i, j] or name globs", "array skip");
    for (size_t i = 0; skip.is_sequence() && i < skip.size(); ++i) {
      yaml::Node item = skip.item(i);
      ArraySpec::Skip s;
      s.mark = item.mark();
      if (item.is_sequence()) s.index = load::scalar_list(item, "an array skip index", diag);
      else if (item.is_scalar()) s.glob = load::scalar(item, "an array skip glob", diag);
      else load::expected(diag, item, "an index tuple [i, j] or a name glob", "array skip");
      spec.skip.push_back(std::move(s));
    }
    a.finish();
    o.array = std::move(spec);
  } else {
    if (name.valid()) o.name = load::scalar(name, "the object name", diag);
    else if (r.ok()) diag.error(o.mark, "object is missing the required key 'name'");
    if (o.name.present && !is_valid_name(o.name.text)) {
      diag.error(o.name.mark, fmt::format("expected an object name (a letter, then letters, digits, '_' or '-'), found '{}'",
                                          o.name.text));
      o.name.present = false;
    }
  }
  o.location = load::vec3(r.take("location"), "location", diag);
  o.orientation = load::vec3(r.take("orientation"), "orientation", diag);
  o.parent = load::scalar(r.take("parent"), "parent", diag);
  o.at = load::scalar(r.take("at"), "at", diag);
  if (o.at.present && o.parent.present)
    diag.error(o.at.mark, "an object is placed by 'parent' or by 'at' (a frame of its parent), not both");
  o.geomodel = load::scalar(r.take("geomodel"), "geomodel", diag);
  o.color = load::scalar(r.take("color"), "color", diag);
  for (auto& [k, v] : r.rest()) {
    // Attribute names are checked against the type at compile time, with suggestions there.
    if (!v.is_scalar() && !v.is_null()) {
      load::expected(diag, v, "a value", fmt::format("attribute '{}'", k.text()));
      continue;
    }
    o.attributes.push_back({std::string(k.text()), k.mark(), load::scalar(v, "an attribute", diag)});
  }
  return o;
}

SelectorSpec read_selector(yaml::Node node, std::string_view what, Diagnostics& diag) {
  SelectorSpec s;
  s.mark = node.valid() ? node.mark() : SourceMark{};
  s.items = load::scalar_list(node, what, diag);
  if (node.valid() && s.items.empty()) load::expected(diag, node, "a name, glob, type:T or a list of these", what);
  // An empty item (`a: ` half typed, `[Drum_1, ~]`) selects nothing: never a silent pass.
  for (const Scalar& item : s.items)
    if (item.null) {
      diag.error(item.mark, fmt::format("expected a name, glob, type:T or a list of these for {}, found nothing", what));
      s.items.clear();
      break;
    }
  return s;
}

/// An object's name where one is required (`device:`, `container:`, `carrying:`): left empty
/// (`device: `, `device: ~`: null), it is an input error, never a rule left out. ("" is a name
/// that names no object: the compile says so.)
Scalar object_name(yaml::Node node, std::string_view what, Diagnostics& diag) {
  Scalar s = load::scalar(node, what, diag);
  if (s.present && s.null) diag.error(s.mark, fmt::format("expected an object name for {}, found nothing", what));
  return s;
}

std::optional<ConstraintKind> read_kind(std::string_view kind, yaml::Node body, Diagnostics& diag) {
  if (kind == "bound") {
    BoundSpec b;
    if (body.is_sequence()) {
      if (body.size() != 3) {
        load::expected(diag, body, "[lhs, OP, rhs]", "bound");
        return std::nullopt;
      }
      b.lhs = load::scalar(body.item(0), "bound lhs", diag);
      b.rhs = load::scalar(body.item(2), "bound rhs", diag);
      yaml::Node op = body.item(1);
      b.op_mark = op.mark();
      auto parsed = op.is_scalar() ? relop_from(op.text()) : std::nullopt;
      if (!parsed) load::expected(diag, op, "LT, GT, EQ, LE, GE (or < > == <= >=)", "the bound operator");
      b.op = parsed.value_or(RelOp::LT);
      return b;
    }
    MapReader r(body, "bound constraint", diag);
    if (!r.ok()) return std::nullopt;
    b.lhs = load::scalar(r.require("lhs"), "bound lhs", diag);
    b.rhs = load::scalar(r.require("rhs"), "bound rhs", diag);
    b.lhs_tol = load::scalar(r.take("lhs_tol"), "lhs_tol", diag);
    b.rhs_tol = load::scalar(r.take("rhs_tol"), "rhs_tol", diag);
    b.eps = load::scalar(r.take("eps"), "eps", diag);
    yaml::Node op = r.require("op");
    if (op.valid()) {
      b.op_mark = op.mark();
      auto parsed = op.is_scalar() ? relop_from(op.text()) : std::nullopt;
      if (!parsed) load::expected(diag, op, "LT, GT, EQ, LE, GE (or < > == <= >=)", "the bound operator");
      b.op = parsed.value_or(RelOp::LT);
    }
    r.finish();
    return b;
  }
  if (kind == "expr") {
    ExprSpec e{load::scalar(body, "expr", diag)};
    if (e.expr.null) {  // `expr:` with nothing after it: an error, never a constraint dropped
      if (body.is_null()) load::expected(diag, body, "an expression", "expr");
      return std::nullopt;
    }
    return e;
  }
  MapReader r(body, fmt::format("{} constraint", kind), diag);
  if (!r.ok()) return std::nullopt;
  auto allow_empty = [&](SelectorSpec& s) { s.allow_empty = load::boolean(r.take("allow_empty"), "allow_empty", diag); };
  ConstraintKind out;
  if (kind == "plugin") {
    PluginSpec p;
    p.cls = load::scalar(r.require("class"), "plugin class", diag);
    p.attributes = load::scalar_list(r.take("attributes"), "plugin attributes", diag);
    yaml::Node args = r.take("args");
    p.args = args.valid() ? load::to_json(args) : nlohmann::ordered_json::object();
    out = std::move(p);
  } else if (kind == "clearance") {
    ClearanceSpec c;
    yaml::Node a = r.take("a"), b = r.take("b");
    if (a.valid()) c.a = read_selector(a, "clearance a", diag);
    if (b.valid()) c.b = read_selector(b, "clearance b", diag);
    yaml::Node objects = r.take("objects");
    if (objects.valid()) c.objects = read_selector(objects, "clearance objects", diag);
    // allow_empty belongs to whichever selection the constraint makes.
    bool empty_ok = load::boolean(r.take("allow_empty"), "allow_empty", diag);
    for (auto* sel : {&c.a, &c.b, &c.objects})
      if (*sel) (*sel)->allow_empty = empty_ok;
    if (objects.valid() == (a.valid() || b.valid()) || a.valid() != b.valid())
      diag.error(r.mark(), "clearance takes either a pair {a, b} or a set {objects}");
    c.min = load::scalar(r.require("min"), "clearance min", diag);
    c.eps = load::scalar(r.take("eps"), "eps", diag);
    out = std::move(c);
  } else if (kind == "no_overlap") {
    NoOverlapSpec n{read_selector(r.require("objects"), "no_overlap objects", diag), {}};
    allow_empty(n.objects);
    n.eps = load::scalar(r.take("eps"), "eps", diag);
    out = std::move(n);
  } else if (kind == "inside") {
    InsideSpec in;
    in.objects = read_selector(r.require("objects"), "inside objects", diag);
    allow_empty(in.objects);
    in.container = object_name(r.require("container"), "inside container", diag);
    in.min = load::scalar(r.take("min"), "inside min", diag);
    in.eps = load::scalar(r.take("eps"), "eps", diag);
    in.faces = load::scalar_list(r.take("faces"), "inside faces", diag);
    out = std::move(in);
  } else {  // reach
    ReachSpec re;
    re.device = object_name(r.require("device"), "reach device", diag);
    // Targets: selectors (`Drum_*`, `type:drum`, `Drum_3.top`) and world poses ({xyz, rpy}).
    yaml::Node targets = r.require("targets");
    re.targets.mark = targets.valid() ? targets.mark() : r.mark();
    bool told_empty = false;  // an empty target, said where it is
    auto target = [&](yaml::Node item) {
      if (item.is_map()) {
        MapReader pr(item, "reach target pose", diag);
        re.poses.push_back({load::pose(pr, diag), item.mark()});
        pr.finish();
      } else {
        Scalar t = load::scalar(item, "reach targets", diag);
        if (t.present && t.null) {
          diag.error(t.mark, "expected an object, OBJECT.FRAME, a glob or type:T for reach targets, found nothing");
          told_empty = true;
        } else {
          re.targets.items.push_back(std::move(t));
        }
      }
    };
    if (targets.is_sequence()) {
      for (size_t i = 0; i < targets.size(); ++i) target(targets.item(i));
    } else if (targets.valid()) {
      target(targets);
    }
    if (targets.valid() && re.targets.items.empty() && re.poses.empty() && !told_empty)
      load::expected(diag, targets, "a name, glob, type:T, Object.frame, {xyz, rpy} or a list of these", "reach targets");
    allow_empty(re.targets);
    re.frame = load::scalar(r.take("frame"), "reach frame", diag);
    yaml::Node orientation = r.take("orientation");
    if (orientation.valid()) {  // one error for a value that is not free or match, whatever it is
      const std::string word = orientation.is_scalar() ? load::text(orientation, "orientation", diag) : "";
      if (word == "match") re.match_orientation = true;
      else if (word != "free") load::expected(diag, orientation, "free or match", "reach orientation");
    }
    yaml::Node offset = r.take("offset");
    if (offset.valid()) {
      MapReader o(offset, "reach offset", diag);
      re.offset = load::pose(o, diag);
      o.finish();
    }
    re.position_tol = load::scalar(r.take("position_tol"), "position_tol", diag);
    re.angle_tol = load::scalar(r.take("angle_tol"), "angle_tol", diag);
    re.carrying = object_name(r.take("carrying"), "reach carrying", diag);
    out = std::move(re);
  }
  r.finish();
  return out;
}

std::optional<ConstraintSpec> read_constraint(yaml::Node node, Diagnostics& diag) {
  static const std::vector<std::string> kKinds(kConstraintKindNames.begin(), kConstraintKindNames.end());
  MapReader r(node, "constraint", diag);
  if (!r.ok()) return std::nullopt;
  ConstraintSpec c;
  c.mark = node.mark();
  yaml::Node name = r.require("name");
  c.name = load::text(name, "constraint name", diag);
  if (name.valid() && name.is_scalar() && c.name.empty()) diag.error(name.mark(), "a constraint name must not be empty");
  c.description = load::text(r.take("description"), "description", diag);
  yaml::Node severity = r.take("severity");
  if (severity.valid()) {
    const std::string word = severity.is_scalar() ? load::text(severity, "severity", diag) : "";
    if (word == "warning") c.severity = Severity::Warning;
    else if (word != "error") load::expected(diag, severity, "error or warning", "severity");
  }
  std::optional<ConstraintKind> kind;
  int kinds = 0;
  for (const std::string& k : kKinds) {
    yaml::Node body = r.take(k);
    if (!body.valid()) continue;
    if (++kinds > 1) {
      diag.error(r.node().find(k).mark(), "a constraint has exactly one kind; found a second one here");
      continue;
    }
    kind = read_kind(k, body, diag);
  }
  if (kinds == 0) {
    // Name the unknown key if there is one; it is probably a misspelt kind.
    auto rest = r.rest();
    if (!rest.empty())
      diag.error(rest[0].first.mark(), fmt::format("unknown constraint kind '{}'{}; expected one of {}",
                                                   rest[0].first.text(), did_you_mean(rest[0].first.text(), kKinds),
                                                   fmt::join(kKinds, ", ")));
    else
      diag.error(c.mark, fmt::format("constraint '{}' has no kind; expected one of {}", c.name, fmt::join(kKinds, ", ")));
    return std::nullopt;
  }
  // An expr has no mapping of its own: its aggregates' allow_empty stands beside it.
  yaml::Node empty = r.take("allow_empty");
  if (empty.valid()) {
    if (auto* e = kind ? std::get_if<ExprSpec>(&*kind) : nullptr)
      e->allow_empty = load::boolean(empty, "allow_empty", diag);
    else if (kind)
      diag.error(empty.mark(), "allow_empty belongs inside the constraint's kind (beside objects or targets); beside the kind only for expr");
  }
  r.finish();
  if (!kind) return std::nullopt;
  c.kind = std::move(*kind);
  return c;
}

}  // namespace

std::optional<VaultSpec> load_vault(const std::string& path, Sources& sources, Diagnostics& diag) {
  uint32_t file = read_source(path, sources, diag);
  if (file == 0) return std::nullopt;
  return load_vault(file, sources, diag);
}

std::optional<VaultSpec> load_vault(uint32_t file, Sources& sources, Diagnostics& diag) {
  const std::string& path = sources.path(file);
  StageTimer timer;
  yaml::Document doc = yaml::parse(sources, file, diag);
  timer.lap("parse");
  if (doc.empty()) return std::nullopt;
  // A scenario, campaign or sweep named where a vault is expected (`sscs check receiving.yaml`):
  // one error that says what it is and what reads it, not one per key it has and lacks.
  if (doc.root().is_map())
    for (const char* kind : {"scenario", "campaign", "sweep"})
      if (doc.root().find(kind).valid() && !doc.root().find("objects").valid()) {
        SourceMark at = doc.root().mark();
        for (size_t i = 0; i < doc.root().size(); ++i)
          if (doc.root().key(i).text() == kind) at = doc.root().key(i).mark();
        diag.error(at,
                   fmt::format("expected a vault file, found a {} file ('{}:' at its top); {}", kind, kind,
                               std::string_view(kind) == "sweep" ? "run it with `sscs sweep FILE`" : "run it with `sscs simulate FILE`"));
        return std::nullopt;
      }
  MapReader root(doc.root(), "a vault file", diag);
  if (!root.ok()) return std::nullopt;
  load::check_version(root, diag);
  VaultSpec v;
  v.path = path;
  yaml::Node name = root.require("vault");
  v.name = load::name(name, "the vault", diag);
  v.mark = name.valid() ? name.mark() : root.mark();
  v.description = load::text(root.take("description"), "description", diag);
  v.library = load::scalar_list(root.take("library"), "library", diag);
  v.standard_library = load::boolean(root.take("standard_library"), "standard_library", diag, true);
  v.plugins = load::scalar_list(root.take("plugins"), "plugins", diag);
  MapReader params(root.take("parameters"), "parameters", diag);
  for (auto& [k, val] : params.rest()) v.parameters.push_back(read_parameter(k, val, diag));
  yaml::Node objects = root.take("objects");
  if (objects.valid() && !objects.is_sequence()) load::expected(diag, objects, "a sequence of objects", "objects");
  else if (objects.valid()) {
    v.objects.reserve(objects.size());
    for (size_t i = 0; i < objects.size() && !diag.full(); ++i) v.objects.push_back(read_object(objects.item(i), diag));
  }
  yaml::Node constraints = root.take("constraints");
  if (constraints.valid() && !constraints.is_sequence())
    load::expected(diag, constraints, "a sequence of constraints", "constraints");
  else if (constraints.valid()) {
    v.constraints.reserve(constraints.size());
    for (size_t i = 0; i < constraints.size() && !diag.full(); ++i)
      if (auto c = read_constraint(constraints.item(i), diag)) v.constraints.push_back(std::move(*c));
  }
  MapReader cameras(root.take("cameras"), "cameras", diag);
  for (auto& [k, val] : cameras.rest()) {
    std::string name = load::name(k, "a camera", diag);
    v.cameras.emplace_back(name, load::read_camera(val, diag, false));
  }
  root.finish();
  return v;
}

}  // namespace sscs
