// The compile driver and its passes: names -> types -> parameters -> arrays -> objects ->
// values in dependency order -> constraints -> freeze.
#include "compile/compile.h"

#include "core/pose.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "compile/state.h"
#include "compile/cameras.h"
#include "compile/values.h"
#include "core/names.h"
#include "core/selection_calls.h"


namespace sscs {

// ---- Workcell lookups --------------------------------------------------------------------------

int Workcell::find_object(std::string_view n) const {
  auto it = std::lower_bound(by_name.begin(), by_name.end(), n,
                             [&](int i, std::string_view key) { return objects[i].name < key; });
  return it != by_name.end() && objects[*it].name == n ? *it : -1;
}

std::vector<std::string> Workcell::frame_names(int object) const {
  std::vector<std::string> names = {"origin", "top"};
  const TypeTemplates& tt = types[objects[object].type].templates;
  const double* attributes = &values[objects[object].first_slot + kFirstAttributeSlot];
  for (const FrameTemplate& f : tt.frames) {
    if (!f.repeat) names.push_back(f.name);
    else f.repeat->each(attributes, [&](const double* at) { names.push_back(f.name_of(at)); });
  }
  if (tt.device) {
    names.push_back("tool");
    for (const PartTemplate& p : tt.device->parts) names.push_back(p.name);
  }
  std::sort(names.begin() + 2, names.end(), [](const std::string& a, const std::string& b) { return natural_less(a, b); });
  names.erase(std::unique(names.begin() + 2, names.end()), names.end());
  names.erase(std::remove_if(names.begin() + 2, names.end(), [](const std::string& n) { return n == "origin" || n == "top"; }),
              names.end());
  return names;
}

std::optional<Eigen::Isometry3d> Workcell::named_frame(int object, std::string_view name) const {
  const TypeTemplates& tt = types[objects[object].type].templates;
  const double* attributes = &values[objects[object].first_slot + kFirstAttributeSlot];
  std::optional<Eigen::Isometry3d> found;
  if (name == "origin") found = Eigen::Isometry3d::Identity();
  for (const FrameTemplate& f : tt.frames)
    if (auto X = f.find(attributes, name)) found = X;  // (a later one of the name replaces an earlier)
  return found;
}

Eigen::Isometry3d Workcell::local_pose(int object) const {
  const Object& o = objects[object];
  const double* v = &values[o.first_slot];
  Eigen::Isometry3d X = make_pose({v[kLocationSlot], v[kLocationSlot + 1], v[kLocationSlot + 2]},
                                  {v[kOrientationSlot], v[kOrientationSlot + 1], v[kOrientationSlot + 2]});
  // Placed `at` a frame of its parent: its location and orientation are in that frame.
  if (!o.at.empty() && o.parent >= 0)
    if (auto at = named_frame(o.parent, o.at)) X = *at * X;
  return X;
}

Eigen::Isometry3d Workcell::pose_in_world(int object, std::vector<std::optional<Eigen::Isometry3d>>& known) const {
  if (known[object]) return *known[object];
  const Object& o = objects[object];
  Eigen::Isometry3d X = local_pose(object);
  if (o.parent >= 0) X = pose_in_world(o.parent, known) * X;
  known[object] = X;
  return X;
}

int Workcell::find_type(std::string_view n) const {
  for (size_t i = 0; i < types.size(); ++i)
    if (types[i].name == n) return static_cast<int>(i);
  return -1;
}

std::optional<std::vector<int>> Workcell::select(std::string_view item) const {
  std::vector<int> out;
  if (item.size() >= 2 && item.front() == '[' && item.back() == ']') {
    std::vector<int> removed;
    for (std::string_view piece : split_selector_list(item)) {
      const bool remove = piece.starts_with('!');
      auto found = select(remove ? piece.substr(1) : piece);
      if (!found) return std::nullopt;
      (remove ? removed : out).insert((remove ? removed : out).end(), found->begin(), found->end());
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    std::erase_if(out, [&](int o) { return std::find(removed.begin(), removed.end(), o) != removed.end(); });
    return out;
  }
  if (item.starts_with("at:")) {
    // at:OBJECT.FRAME: what stands at those frames: placed `at:` one of them, or with its origin
    // where one of them is (within 1 mm: resting on it, placed at another name of the same
    // place, as a rack's slot_3_1_3 and top_3).
    const std::string_view frames = item.substr(3);
    const size_t dot = frames.find('.');
    if (dot == std::string_view::npos) return std::nullopt;
    const std::string_view object_glob = frames.substr(0, dot), frame_glob = frames.substr(dot + 1);
    if (object_glob.find_first_of("*?") == std::string_view::npos && find_object(object_glob) < 0) return std::nullopt;
    std::vector<char> chosen(objects.size(), 0);
    for (size_t i = 0; i < objects.size(); ++i) {
      const Object& o = objects[i];
      if (o.parent >= 0 && !o.at.empty() && glob_match(object_glob, objects[o.parent].name) && glob_match(frame_glob, o.at))
        chosen[i] = 1;
    }
    std::vector<std::pair<int, Eigen::Vector3d>> places;  // (owner, where in the world)
    std::vector<std::optional<Eigen::Isometry3d>> world(objects.size());
    for (size_t k = 0; k < objects.size(); ++k) {
      if (!glob_match(object_glob, objects[k].name)) continue;
      for (const std::string& name : frame_names(static_cast<int>(k)))
        if (glob_match(frame_glob, name))
          if (auto X = named_frame(static_cast<int>(k), name)) places.emplace_back(static_cast<int>(k), pose_in_world(static_cast<int>(k), world) * X->translation());
    }
    if (!places.empty())
      for (size_t i = 0; i < objects.size(); ++i) {
        if (chosen[i] || types[objects[i].type].container) continue;
        const Eigen::Vector3d at = pose_in_world(static_cast<int>(i), world).translation();
        for (const auto& [owner, p] : places) {
          if ((at - p).norm() > 1e-3) continue;
          bool holds_owner = false;  // the owner itself or what it stands in is no object at its frame
          for (int a = owner; a >= 0 && !holds_owner; a = objects[a].parent) holds_owner = a == static_cast<int>(i);
          if (holds_owner) continue;
          chosen[i] = 1;
          break;
        }
      }
    for (size_t i = 0; i < objects.size(); ++i)
      if (chosen[i]) out.push_back(static_cast<int>(i));
    return out;
  }
  if (item.starts_with("type:")) {
    int t = find_type(item.substr(5));
    if (t < 0) return std::nullopt;
    for (size_t i = 0; i < objects.size(); ++i)
      if (is_a(objects[i].type, t)) out.push_back(static_cast<int>(i));
  } else if (item.find_first_of("*?") != std::string_view::npos) {  // "*" and globs
    for (size_t i = 0; i < objects.size(); ++i)
      if (glob_match(item, objects[i].name)) out.push_back(static_cast<int>(i));
  } else {
    int o = find_object(item);
    if (o < 0) return std::nullopt;
    out.push_back(o);
  }
  return out;
}

std::vector<int> Workcell::lineage(int t) const {
  std::vector<int> out;
  for (; t >= 0; t = types[t].base) out.push_back(t);
  return out;
}

bool Workcell::is_a(int t, int ancestor) const {
  const std::vector<int> line = lineage(t);
  return std::find(line.begin(), line.end(), ancestor) != line.end();
}

bool Workcell::nested(int a, int b) const {
  // Only a container's box is a space its descendants stand in (a rack in its room). Any other
  // ancestor is a solid its descendants rest on: a pallet on a rack, a drum on a cart, a drum
  // `at` a rack's slot; run through by its beam is an overlap (it passed: the spec's wording
  // exempted every `parent` link, so a drum parented to its rack passed inside the beams).
  auto holds = [&](int outer, int inner) {
    if (!types[objects[outer].type].container) return false;
    for (int p = objects[inner].parent; p >= 0; p = objects[p].parent)
      if (p == outer) return true;
    return false;
  };
  return a == b || holds(a, b) || holds(b, a);
}

bool Workcell::related(int a, int b) const {
  for (int p = a; p >= 0; p = objects[p].parent)
    if (p == b) return true;
  for (int p = b; p >= 0; p = objects[p].parent)
    if (p == a) return true;
  return false;
}

// ---- CompileState helpers -----------------------------------------------------------------------

std::vector<std::string_view> split_selector_list(std::string_view list) {
  std::vector<std::string_view> out;
  if (list.size() < 2 || list.front() != '[' || list.back() != ']') return {list};
  std::string_view inner = list.substr(1, list.size() - 2);
  for (size_t start = 0; start <= inner.size();) {
    size_t comma = inner.find(',', start);
    if (comma == std::string_view::npos) comma = inner.size();
    std::string_view piece = inner.substr(start, comma - start);
    while (!piece.empty() && piece.front() == ' ') piece.remove_prefix(1);
    while (!piece.empty() && piece.back() == ' ') piece.remove_suffix(1);
    // An item may be quoted as a YAML list's is (`["*", "!Hall"]`): the quotes are no part of it
    // (a quoted "!..." was taken for an object name and removed nothing).
    if (piece.size() >= 2 && (piece.front() == '"' || piece.front() == '\'') && piece.back() == piece.front())
      piece = piece.substr(1, piece.size() - 2);
    if (!piece.empty()) out.push_back(piece);
    start = comma + 1;
  }
  return out;
}

bool CompileState::is_unbuilt(std::string_view name) const {
  if (unbuilt.count(std::string(name))) return true;
  // An instance name of a dropped array: the pattern with each {i} {j} {k} a run of digits.
  for (const std::string& pattern : unbuilt_arrays) {
    size_t p = 0, n = 0;
    bool match = true;
    while (match && p < pattern.size()) {
      if (pattern.compare(p, 3, "{i}") == 0 || pattern.compare(p, 3, "{j}") == 0 || pattern.compare(p, 3, "{k}") == 0) {
        const size_t digits = n;
        while (n < name.size() && name[n] >= '0' && name[n] <= '9') ++n;
        match = n > digits;
        p += 3;
      } else {
        match = n < name.size() && name[n] == pattern[p];
        ++n, ++p;
      }
    }
    if (match && n == name.size()) return true;
  }
  return false;
}

bool CompileState::may_select_unbuilt(std::string_view item) const {
  if (item.starts_with('!')) return false;
  if (item.starts_with("at:")) {
    item.remove_prefix(3);
    item = item.substr(0, item.find('.'));
  }
  if (item.starts_with("type:")) {  // `type:cask` where objects of cask (or of a type extending it) were dropped
    std::string_view type = item.substr(5);
    type = type.substr(0, type.find('.'));
    const int t = wc.find_type(type);
    for (const std::string& dropped : unbuilt_types) {
      if (dropped == type) return true;
      const int d = wc.find_type(dropped);
      if (t >= 0 && d >= 0 && wc.is_a(d, t)) return true;
    }
    return false;
  }
  if (unbuilt.empty() && unbuilt_arrays.empty()) return false;
  if (item.find_first_of("*?") == std::string_view::npos) return is_unbuilt(item);
  for (const std::string& name : unbuilt)
    if (glob_match(item, name)) return true;
  for (std::string example : unbuilt_arrays) {  // an instance name of the pattern: each index 1
    for (const char* index : {"{i}", "{j}", "{k}"})
      for (size_t at; (at = example.find(index)) != std::string::npos;) example.replace(at, 3, "1");
    if (glob_match(item, example)) return true;
  }
  return false;
}

uint32_t CompileState::new_slots(size_t n) {
  auto first = static_cast<uint32_t>(wc.values.size());
  wc.values.resize(wc.values.size() + n, 0.0);
  slot_pending.resize(wc.values.size(), -1);
  slot_failed.resize(wc.values.size(), false);
  return first;
}

std::string CompileState::slot_name(uint32_t slot) const {
  for (const Parameter& p : wc.parameters)
    if (p.slot == slot) return p.name;
  auto it = std::upper_bound(wc.objects.begin(), wc.objects.end(), slot,
                             [](uint32_t s, const Object& o) { return s < o.first_slot; });
  if (it == wc.objects.begin()) return fmt::format("slot {}", slot);
  const Object& o = *std::prev(it);
  uint32_t k = slot - o.first_slot;
  if (k < kFirstAttributeSlot) return fmt::format("{}.{}", o.name, kPoseSlotNames[k]);
  return fmt::format("{}.{}", o.name, wc.types[o.type].attributes[k - kFirstAttributeSlot].name);
}

std::vector<std::string> CompileState::object_names() const {
  std::vector<std::string> out;
  out.reserve(wc.objects.size());
  for (const Object& o : wc.objects) out.push_back(o.name);
  return out;
}

std::vector<std::string> CompileState::parameter_names() const {
  std::vector<std::string> out;
  for (const Parameter& p : wc.parameters) out.push_back(p.name);
  return out;
}

std::shared_ptr<const Expression> CompileState::parse_expression(const Scalar& s, std::string_view what) {
  auto it = expr_cache.find(s.text);
  if (it != expr_cache.end()) return it->second;
  Expression::Error err;
  auto e = Expression::parse(s.text, &err);
  if (!e) {
    diag.error(mark_at(s, err.position), fmt::format("cannot read '{}' as a number, unit value or expression for {}: {}",
                                                     s.text, what, without_position(err.message)));
    return nullptr;
  }
  auto shared = std::make_shared<const Expression>(std::move(*e));
  expr_cache.emplace(s.text, shared);
  return shared;
}

std::optional<Operand> member_operand(const Workcell& wc, int obj, std::string_view member, bool allow_bbox, std::string* why) {
  const Object& o = wc.objects[obj];
  const ObjectType& type = wc.types[o.type];
  Operand op;
  op.text = fmt::format("{}.{}", o.name, member);
  op.object = obj;
  op.kind = Operand::Kind::Slot;
  auto component = [&](std::string_view prefix, std::initializer_list<const char*> names, uint32_t base,
                       Dim dim) -> std::optional<Operand> {
    std::string_view rest = member.substr(prefix.size());
    int k = 0;
    for (const char* n : names) {
      if (rest == n) {
        op.slot = o.first_slot + base + k;
        op.dim = dim;
        return op;
      }
      ++k;
    }
    *why = fmt::format("expected {}{} in reference '{}'", prefix, fmt::join(names, fmt::format(" or {}", prefix)), op.text);
    return std::nullopt;
  };
  if (member.starts_with("location.")) return component("location.", {"x", "y", "z"}, kLocationSlot, Dim::Length);
  if (member.starts_with("orientation."))
    return component("orientation.", {"roll", "pitch", "yaw"}, kOrientationSlot, Dim::Angle);
  if (member.starts_with("bbox.")) {
    std::string_view rest = member.substr(5);
    bool ok = false;
    uint32_t code = 0;
    for (const char* corner : {"min.", "max.", "size."})
      for (const char* axis : {"x", "y", "z"}) {
        if (rest == fmt::format("{}{}", corner, axis)) {
          ok = true;
          op.slot = code;  // corner * 3 + axis, read by the checker from the geometry
        }
        ++code;
      }
    if (!ok) {
      *why = fmt::format("expected bbox.min|max|size.x|y|z in reference '{}'", op.text);
      return std::nullopt;
    }
    if (!allow_bbox) {
      *why = fmt::format("'{}': bounding boxes come from geometry, which is evaluated after attribute values; use them "
                         "in constraints, not in attribute values", op.text);
      return std::nullopt;
    }
    op.kind = Operand::Kind::BoundingBox;
    op.dim = Dim::Length;
    return op;
  }
  int a = type.find_attribute(member);
  if (a < 0) {
    std::vector<std::string> names(kPoseSlotNames.begin(), kPoseSlotNames.end());
    for (const AttributeDef& def : type.attributes) names.push_back(def.name);
    *why = fmt::format("'{}' (a {}) has no attribute '{}'{}", o.name, type.name, member, did_you_mean(member, names));
    return std::nullopt;
  }
  const AttributeDef& def = type.attributes[a];
  if (def.type == AttrType::String || def.type == AttrType::Enum) {
    *why = fmt::format("'{}' is {} attribute; expressions and bounds take numeric values", op.text,
                       def.type == AttrType::Enum ? "an enum" : "a string");
    return std::nullopt;
  }
  op.slot = o.first_slot + kFirstAttributeSlot + a;
  op.dim = def.dim;
  return op;
}

std::optional<Operand> CompileState::resolve_reference(std::string_view ref, SourceMark mark, const ExprScope& scope,
                                                       bool allow_bbox) {
  Operand op;
  op.text = std::string(ref);
  size_t dot = ref.find('.');
  if (dot == std::string_view::npos) {
    if (scope.index) {
      static const char* kIdx[] = {"i", "j", "k"};
      for (int d = 0; d < 3; ++d)
        if (ref == kIdx[d]) {
          op.constant_si = (*scope.index)[d];
          return op;
        }
    }
    if (scope.object >= 0) {
      const Object& self = wc.objects[scope.object];
      int a = wc.types[self.type].find_attribute(ref);
      if (a >= 0) {
        op.kind = Operand::Kind::Slot;
        op.slot = self.first_slot + kFirstAttributeSlot + a;
        op.object = scope.object;
        op.dim = wc.types[self.type].attributes[a].dim;
        return op;
      }
    }
    auto p = parameter_index.find(std::string(ref));
    if (p != parameter_index.end()) {
      const Parameter& param = wc.parameters[p->second];
      op.kind = Operand::Kind::Slot;
      op.slot = param.slot;
      op.dim = param.dim;
      return op;
    }
    std::vector<std::string> candidates = parameter_names();
    if (scope.object >= 0)
      for (const AttributeDef& a : wc.types[wc.objects[scope.object].type].attributes) candidates.push_back(a.name);
    diag.error(mark, fmt::format("unknown name '{}': expected a parameter or a reference Object.attribute{}", ref,
                                 did_you_mean(ref, candidates)));
    return std::nullopt;
  }
  std::string_view object_name = ref.substr(0, dot);
  std::string_view member = ref.substr(dot + 1);
  int obj = wc.find_object(object_name);
  if (obj < 0 && is_unbuilt(object_name)) return std::nullopt;  // already reported
  if (obj < 0) {
    diag.error(mark, fmt::format("unknown object '{}' in reference '{}'{}", object_name, ref,
                                 did_you_mean(object_name, object_names())));
    return std::nullopt;
  }
  std::string why;
  auto member_op = member_operand(wc, obj, member, allow_bbox, &why);
  if (!member_op) {
    diag.error(mark, why);
    return std::nullopt;
  }
  member_op->text = op.text;
  return member_op;
}

bool CompileState::resolve_inputs(const Expression& expr, const Scalar& s, const ExprScope& scope,
                                  std::vector<Operand>& out, bool allow_bbox) {
  bool ok = true;
  out.clear();
  for (const std::string& n : expr.names()) {
    size_t pos = s.text.find(n);
    auto op = resolve_reference(n, mark_at(s, pos == std::string::npos ? 0 : pos), scope, allow_bbox);
    if (!op) {
      ok = false;
      continue;
    }
    out.push_back(*op);
  }
  return ok;
}

void CompileState::evaluate_pending() {
  // Iterative depth-first evaluation: a deep chain of references cannot overflow the stack.
  std::vector<std::pair<int, size_t>> stack;  // pending index, next input to visit
  std::vector<double> inputs;
  for (size_t start = 0; start < pending.size(); ++start) {
    if (pending[start].state != 0) continue;
    stack.push_back({static_cast<int>(start), 0});
    pending[start].state = 1;
    while (!stack.empty()) {
      auto& [p, next] = stack.back();
      PendingValue& pv = pending[p];
      bool descended = false;
      bool failed = false;
      while (next < pv.inputs.size()) {
        const Operand& in = pv.inputs[next++];
        if (in.kind != Operand::Kind::Slot) continue;
        int q = slot_pending[in.slot];
        if (q < 0) continue;
        PendingValue& dep = pending[q];
        if (dep.state == 3) failed = true;
        if (dep.state == 0) {
          dep.state = 1;
          stack.push_back({q, 0});
          descended = true;
          break;
        }
        if (dep.state == 1) {
          // A cycle: the stack from q up to here, then q again.
          std::vector<std::string> path;
          auto from = std::find_if(stack.begin(), stack.end(), [&](const auto& e) { return e.first == q; });
          for (auto it = from; it != stack.end(); ++it) path.push_back(slot_name(pending[it->first].slot));
          path.push_back(slot_name(dep.slot));
          diag.error(dep.source->mark, fmt::format("values depend on each other in a cycle: {}", fmt::join(path, " -> ")));
          for (auto it = from; it != stack.end(); ++it) pending[it->first].state = 3;
          failed = true;
        }
      }
      if (descended) continue;
      PendingValue& cur = pending[stack.back().first];
      if (cur.state == 1 && !failed) {
        inputs.clear();
        for (const Operand& in : cur.inputs)
          inputs.push_back(in.kind == Operand::Kind::Slot ? wc.values[in.slot] : in.constant_si);
        double v = cur.expr->evaluate(inputs.data());
        if (!std::isfinite(v)) {
          diag.error(cur.source->mark, fmt::format("'{}' for {} has no finite value: {}", cur.source->text, slot_name(cur.slot),
                                                   nonfinite_reason(v)));
          cur.state = 3;
        } else {
          wc.values[cur.slot] = v + cur.add;
          cur.state = 2;
        }
      } else if (cur.state == 1) {
        cur.state = 3;
      }
      stack.pop_back();
    }
  }
}

// ---- passes ----------------------------------------------------------------------------------------

namespace {

/// Stores a written value into `slot`: a number now, an expression for later.
void assign(CompileState& st, uint32_t slot, const Scalar& s, const AttributeDef* def, Dim dim, const ExprScope& scope,
            std::string_view what, double add = 0) {
  if (def && (def->type == AttrType::String || def->type == AttrType::Enum)) {
    if (s.null) {
      st.diag.error(s.mark, fmt::format("expected a {} for {}, found nothing", attr_type_name(def->type), what));
      return;
    }
    if (def->type == AttrType::Enum && std::find(def->values.begin(), def->values.end(), s.text) == def->values.end()) {
      st.diag.error(s.mark, fmt::format("expected one of {} for {}, found '{}'{}", fmt::join(def->values, ", "), what,
                                        s.text, did_you_mean(s.text, def->values)));
      return;
    }
    if (st.wc.texts.size() < st.wc.values.size()) st.wc.texts.resize(st.wc.values.size());
    st.wc.texts[slot] = s.text;
    return;
  }
  if (def && def->type == AttrType::Boolean) {
    if (!s.quoted && (s.text == "true" || s.text == "false")) {
      st.wc.values[slot] = s.text == "true" ? 1.0 : 0.0;
    } else {
      st.diag.error(s.mark, fmt::format("expected true or false for {}, found '{}'", what, s.text));
    }
    return;
  }
  ParsedValue v = parse_value(s, dim, what, st.diag);
  if (v.kind == ParsedValue::Kind::Number) {
    if (!std::isfinite(v.si + add)) {  // 1e306 km: finite as written, not in metres
      st.diag.error(s.mark, fmt::format("'{}' for {} is beyond the range of numbers once converted to SI units", s.text, what));
      return;
    }
    st.wc.values[slot] = v.si + add;
    return;
  }
  if (v.kind == ParsedValue::Kind::Error) return;
  auto expr = st.parse_expression(s, what);
  if (!expr) return;
  PendingValue pv;
  pv.slot = slot;
  pv.source = &s;
  pv.expr = expr;
  pv.add = add;
  if (!st.resolve_inputs(*expr, s, scope, pv.inputs)) return;
  if (!check_expression_dimensions(*expr, pv.inputs, s, dim, what, st.diag)) return;
  st.slot_pending[slot] = static_cast<int>(st.pending.size());
  st.pending.push_back(std::move(pv));
}

/// Pass: parameters, with --set overrides, evaluated among themselves.
void compile_parameters(CompileState& st, const CompileOptions& options, std::vector<Scalar>& overrides) {
  const VaultSpec& spec = st.spec;
  overrides.reserve(options.overrides.size());  // pointers into it are kept by pending values
  std::vector<const Scalar*> value_of(spec.parameters.size());
  for (size_t i = 0; i < spec.parameters.size(); ++i) {
    const ParameterSpec& p = spec.parameters[i];
    if (p.name.empty()) continue;
    if (st.parameter_index.count(p.name)) {
      st.diag.error(p.mark, fmt::format("parameter '{}' is defined twice", p.name));
      continue;
    }
    Parameter param;
    param.name = p.name;
    param.slot = st.new_slots(1);
    if (p.type) {
      param.type = *p.type;
      param.dim = dim_of(*p.type);
    } else if (auto q = parse_quantity(p.value.text); q && q->has_unit) {
      param.dim = q->dim;
      param.type = AttrType::Number;
    } else if (!p.value.quoted && (p.value.text == "true" || p.value.text == "false")) {
      param.type = AttrType::Boolean;
    }
    st.parameter_index[p.name] = static_cast<int>(st.wc.parameters.size());
    st.wc.parameters.push_back(param);
    value_of[st.wc.parameters.size() - 1] = &p.value;
  }
  for (const auto& [name, text] : options.overrides) {
    auto it = st.parameter_index.find(name);
    if (it == st.parameter_index.end()) {
      st.diag.error({}, fmt::format("--set {}={}: the vault has no parameter '{}'{}", name, text, name,
                                    did_you_mean(name, st.parameter_names())));
      continue;
    }
    if (std::string why = nonfinite_number(text); !why.empty()) {
      st.diag.error({}, fmt::format("--set {}={}: expected a finite number: {}", name, text, why));
      continue;
    }
    Scalar s;
    s.text = text;
    s.present = true;
    overrides.push_back(s);
    value_of[it->second] = &overrides.back();
  }
  for (size_t i = 0; i < st.wc.parameters.size(); ++i) {
    const Parameter& param = st.wc.parameters[i];
    AttributeDef def;
    def.type = param.type;
    assign(st, param.slot, *value_of[i], &def, param.dim, {}, fmt::format("parameter '{}'", param.name));
  }
  st.evaluate_pending();
  for (size_t i = 0; i < spec.parameters.size(); ++i) {
    const ParameterSpec& p = spec.parameters[i];
    auto it = st.parameter_index.find(p.name);
    if (it == st.parameter_index.end()) continue;
    const Parameter& param = st.wc.parameters[it->second];
    double v = st.wc.values[param.slot];
    const Scalar& written = *value_of[it->second];
    if (param.type == AttrType::Integer && (v != std::floor(v) || v < INT32_MIN || v > INT32_MAX))
      st.diag.error(written.mark, fmt::format("parameter '{}' is an integer from -2147483648 to 2147483647, found {}",
                                              p.name, written.text));
    std::string where = written.mark.valid() ? "" : fmt::format(" (from --set {}={})", p.name, written.text);
    if (p.min.present)
      if (auto lo = literal_si(p.min, param.dim, "the parameter's min", st.diag); lo && v < *lo)
        st.diag.error(written.mark, fmt::format("parameter '{}' is {}, below its min {}{}", p.name,
                                                si_to_file(v, param.dim), p.min.text, where));
    if (p.max.present)
      if (auto hi = literal_si(p.max, param.dim, "the parameter's max", st.diag); hi && v > *hi)
        st.diag.error(written.mark, fmt::format("parameter '{}' is {}, above its max {}{}", p.name,
                                                si_to_file(v, param.dim), p.max.text, where));
  }
}

}  // namespace

std::optional<double> CompileState::number_now(const Scalar& s, Dim dim, std::string_view what, bool parameters_only) {
  ParsedValue v = parse_value(s, dim, what, diag);
  if (v.kind == ParsedValue::Kind::Number) return v.si;
  if (v.kind == ParsedValue::Kind::Error) return std::nullopt;
  auto expr = parse_expression(s, what);
  if (!expr) return std::nullopt;
  std::vector<double> values;
  if (parameters_only) {
    for (const std::string& n : expr->names()) {
      auto it = parameter_index.find(n);
      if (it == parameter_index.end()) {
        diag.error(s.mark, fmt::format("{} may use parameters only; '{}' is not one{}", what, n, did_you_mean(n, parameter_names())));
        return std::nullopt;
      }
      values.push_back(wc.values[wc.parameters[it->second].slot]);
    }
  } else {
    std::vector<Operand> inputs;
    if (!resolve_inputs(*expr, s, {}, inputs)) return std::nullopt;
    if (!check_expression_dimensions(*expr, inputs, s, dim, what, diag)) return std::nullopt;
    for (const Operand& op : inputs) values.push_back(op.kind == Operand::Kind::Slot ? wc.values[op.slot] : op.constant_si);
  }
  double r = expr->evaluate(values.data());
  if (!std::isfinite(r)) {
    diag.error(s.mark, fmt::format("{} '{}' has no finite value: {}", what, s.text, nonfinite_reason(r)));
    return std::nullopt;
  }
  return r;
}

namespace {

constexpr size_t kMaxObjects = 2'000'000;

/// Pass: one Object per written object or array instance, with unique names and known types.
void expand_objects(CompileState& st) {
  std::vector<std::string> type_names;
  for (const ObjectType& t : st.wc.types) type_names.push_back(t.name);
  for (const ObjectSpec& o : st.spec.objects) {
    if (o.type.empty()) continue;
    auto t = std::find_if(st.wc.types.begin(), st.wc.types.end(), [&](const ObjectType& x) { return x.name == o.type; });
    if (t == st.wc.types.end()) {
      std::string hint = did_you_mean(o.type, type_names);
      // Both hints: a near name may be a typo, or the type may be a plugin's that is not loaded.
      if (st.plugins->files().empty()) hint += " (no plugins are loaded: a plugin's type needs --plugins DIR)";
      st.diag.error(o.type_mark, fmt::format("unknown type '{}'{}", o.type, hint));
      if (o.name.present) st.unbuilt.insert(o.name.text);
      if (o.array) st.unbuilt_arrays.push_back(o.array->name_pattern.text);  // no "unknown object 'Crate_3'" after it
      st.unbuilt_types.insert(o.type);  // nor "type:crat selects no objects"
      continue;
    }
    int type = static_cast<int>(t - st.wc.types.begin());
    // A type whose files are broken is an error where it is used (once), its base's problems too;
    // no object is built of it.
    // A base's problems say which type used here extends it (an error in a file the vault never
    // names read as if out of nowhere).
    for (int k : st.wc.lineage(type))
      if (st.reported_types.insert(k).second)
        for (const Diagnostic& d : st.wc.types[k].problems) {
          const std::string message =
              k == type ? d.message : fmt::format("{} (in type '{}', which '{}' extends)", d.message, st.wc.types[k].name, st.wc.types[type].name);
          if (d.warning) st.diag.warning(d.mark, message);
          else st.diag.error(d.mark, message);
        }
    if (st.wc.types[type].broken) {
      if (o.name.present) st.unbuilt.insert(o.name.text);
      if (o.array) st.unbuilt_arrays.push_back(o.array->name_pattern.text);
      st.unbuilt_types.insert(o.type);
      continue;
    }
    // A library reused from another vault's compile holds the templates it needed only (its
    // caller asks for the whole library: CompileOptions::whole_library).
    if (!st.wc.types[type].shaped)
      throw std::logic_error(fmt::format("type '{}' is in a reused library without its templates (compile it with whole_library)", o.type));
    auto add = [&](std::string name, SourceMark mark, std::array<int, 3> index, std::array<double, 3> offset) {
      Object obj;
      obj.name = std::move(name);
      obj.type = type;
      obj.mark = mark;
      st.wc.objects.push_back(std::move(obj));
      st.object_spec.push_back(&o);
      st.array_index.push_back(index);
      st.array_offset.push_back(offset);
    };
    if (!o.array) {
      if (o.name.present) add(o.name.text, o.name.mark, {0, 0, 0}, {0, 0, 0});
      continue;
    }
    const ArraySpec& a = *o.array;
    std::array<int, 3> count = {1, 1, 1};
    std::array<double, 3> pitch = {0, 0, 0};
    bool ok = true;
    for (size_t d = 0; d < a.count.size() && d < 3; ++d) {
      auto n = st.number_now(a.count[d], Dim::None, "an array count", /*parameters_only=*/true);
      if (!n) {
        ok = false;
        continue;
      }
      if (*n != std::floor(*n) || *n < 1 || *n > 1e6) {
        st.diag.error(a.count[d].mark, fmt::format("expected an array count from 1 to 1000000, found {}", *n));
        ok = false;
        continue;
      }
      count[d] = static_cast<int>(*n);
    }
    for (size_t d = 0; d < 3; ++d) {
      if (!a.pitch[d].present) continue;
      auto p = st.number_now(a.pitch[d], Dim::Length, "an array pitch", /*parameters_only=*/true);
      if (!p) ok = false;
      else pitch[d] = *p;
      // Step d of the pitch moves the array's d-th index: with fewer counts it moves nothing
      // (two rows at one place, and 28 drums in each other's drums, said nothing).
      if (p && *p != 0 && d >= a.count.size()) {
        st.diag.error(a.pitch[d].mark, fmt::format("the array's pitch steps along {} by {}, but the array has {} count{}: a step along {} "
                                                   "moves index {{{}}}, so give count: [{}] (name with {{{}}})",
                                                   "xyz"[d], a.pitch[d].text, a.count.size(), a.count.size() == 1 ? "" : "s", "xyz"[d],
                                                   "ijk"[d], d == 1 ? "1, n" : "1, 1, n", "ijk"[d]));
        ok = false;
      }
    }
    const std::string& pattern = a.name_pattern.text;
    for (size_t d = a.count.size(); d < 3; ++d)
      if (pattern.find(fmt::format("{{{}}}", "ijk"[d])) != std::string::npos) {
        st.diag.error(a.name_pattern.mark, fmt::format("array name '{}' uses {{{}}} but count has only {} entries",
                                                       pattern, "ijk"[d], a.count.size()));
        ok = false;
      }
    if (!ok) {
      st.unbuilt_arrays.push_back(pattern);
      continue;
    }
    if (static_cast<double>(count[0]) * count[1] * count[2] + st.wc.objects.size() > kMaxObjects) {
      st.diag.error(a.mark, fmt::format("array makes more than {} objects", kMaxObjects));
      st.unbuilt_arrays.push_back(pattern);
      continue;
    }
    // skip: index tuples (as many indices as counts, each within its count) and name globs.
    std::vector<std::array<int, 3>> skip_index(a.skip.size(), std::array<int, 3>{0, 0, 0});
    std::vector<char> skip_used(a.skip.size(), 0);
    for (size_t s = 0; s < a.skip.size(); ++s) {
      const ArraySpec::Skip& sk = a.skip[s];
      if (sk.glob.present) continue;
      if (sk.index.size() != a.count.size()) {
        st.diag.error(sk.mark, fmt::format("array skip needs {} indices, one per count, found {}", a.count.size(), sk.index.size()));
        skip_used[s] = 1;  // reported
        continue;
      }
      for (size_t d = 0; d < sk.index.size(); ++d) {
        size_t before = st.diag.count();
        auto n = st.number_now(sk.index[d], Dim::None, "an array skip index", /*parameters_only=*/true);
        if (st.diag.count() != before) {
          skip_used[s] = 1;
          break;
        }
        if (!n || *n != std::floor(*n) || *n < 1 || *n > count[d]) {
          st.diag.error(sk.index[d].mark, fmt::format("expected an index from 1 to {} in array skip, found '{}'", count[d], sk.index[d].text));
          skip_used[s] = 1;
          break;
        }
        skip_index[s][d] = static_cast<int>(*n);
      }
    }
    bool reported = false;
    for (int i = 1; i <= count[0]; ++i)
      for (int j = 1; j <= count[1]; ++j)
        for (int k = 1; k <= count[2]; ++k) {
          std::string name = pattern;
          for (auto [key, v] : {std::pair{"{i}", i}, std::pair{"{j}", j}, std::pair{"{k}", k}})
            for (size_t p; (p = name.find(key)) != std::string::npos;) name.replace(p, 3, std::to_string(v));
          bool skipped = false;
          for (size_t s = 0; s < a.skip.size(); ++s) {
            const ArraySpec::Skip& sk = a.skip[s];
            const std::array<int, 3> at = {i, a.count.size() >= 2 ? j : 0, a.count.size() >= 3 ? k : 0};
            bool hit = sk.glob.present ? glob_match(sk.glob.text, name) : skip_index[s] == at;  // {0,0,0}: invalid
            if (hit) skip_used[s] = 1;
            skipped = skipped || hit;
          }
          if (skipped) continue;
          if (!is_valid_name(name)) {
            if (!reported)
              st.diag.error(a.name_pattern.mark, fmt::format("array name '{}' makes '{}', which is not a valid name", pattern, name));
            reported = true;
            continue;
          }
          add(name, a.name_pattern.mark, {i, j, k}, {(i - 1) * pitch[0], (j - 1) * pitch[1], (k - 1) * pitch[2]});
        }
    for (size_t s = 0; s < a.skip.size(); ++s) {
      if (skip_used[s]) continue;
      const Scalar& g = a.skip[s].glob;
      bool number = g.present && parse_number(g.text).has_value();
      st.diag.error(a.skip[s].mark, fmt::format("array skip '{}' matches no position of the array{}", g.present ? g.text : "this index",
                                                number ? fmt::format(" (an index is a list: [[{}]] leaves out position {})", g.text, g.text) : ""));
    }
  }
  if (st.wc.objects.size() > kMaxObjects) return;
  // Unique names, then the sorted index used by every lookup.
  auto& by_name = st.wc.by_name;
  by_name.resize(st.wc.objects.size());
  for (size_t i = 0; i < by_name.size(); ++i) by_name[i] = static_cast<int>(i);
  std::stable_sort(by_name.begin(), by_name.end(),
                   [&](int a, int b) { return st.wc.objects[a].name < st.wc.objects[b].name; });
  for (size_t i = 1; i < by_name.size(); ++i) {
    const Object& a = st.wc.objects[by_name[i - 1]];
    const Object& b = st.wc.objects[by_name[i]];
    if (a.name == b.name)
      st.diag.error(b.mark, fmt::format("object name '{}' is used twice (first at {})", b.name,
                                        // (a campaign's load clashing with the vault's object: in the vault's file)
                                        a.mark.valid() && a.mark.file != b.mark.file ? fmt::format("{}:{}", st.sources.path(a.mark.file), a.mark.line)
                                                                                      : fmt::format("line {}", a.mark.line)));
  }
  // Slots: location, orientation, then attributes.
  for (Object& obj : st.wc.objects)
    obj.first_slot = st.new_slots(kFirstAttributeSlot + st.wc.types[obj.type].attributes.size());
}

/// `at: OBJECT.FRAME`: the object's parent is OBJECT, and it stands at FRAME (checked once the
/// parent's attributes, which place its frames, are known). An array instance's {i} {j} {k} are
/// its indices.
void place_at(CompileState& st, int i, std::vector<std::string>& names) {
  Object& obj = st.wc.objects[i];
  const ObjectSpec& o = *st.object_spec[i];
  std::string text = o.at.text;
  if (o.array)
    for (auto [key, v] : {std::pair{"{i}", 0}, std::pair{"{j}", 1}, std::pair{"{k}", 2}})
      for (size_t p; (p = text.find(key)) != std::string::npos;) text.replace(p, 3, std::to_string(st.array_index[i][v]));
  const size_t dot = text.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size()) {
    st.diag.error(o.at.mark, fmt::format("expected OBJECT.FRAME for 'at' (a named frame of the object it stands on, as "
                                         "Rack_1.slot_2_1_1), found '{}'", o.at.text));
    return;
  }
  const std::string target = text.substr(0, dot);
  obj.parent = st.wc.find_object(target);
  obj.at = text.substr(dot + 1);
  if (obj.parent < 0 && !st.is_unbuilt(target)) {
    if (names.empty()) names = st.object_names();
    st.diag.error(o.at.mark, fmt::format("'at' names unknown object '{}'{}", target, did_you_mean(target, names)));
  } else if (obj.parent == i) {
    st.diag.error(o.at.mark, fmt::format("object '{}' cannot stand at a frame of its own", obj.name));
    obj.parent = -1;
  }
}

/// Pass: an object placed `at` a frame of its parent names a frame the parent has (its
/// attributes decide which: a rack of 3 levels has no slot_4_1_1).
void check_at_frames(CompileState& st) {
  const ObjectSpec* reported = nullptr;  // an array's instances share their `at`: one error for them
  for (size_t i = 0; i < st.wc.objects.size() && !st.diag.full(); ++i) {
    const Object& obj = st.wc.objects[i];
    if (obj.at.empty() || obj.parent < 0) continue;
    if (st.wc.named_frame(obj.parent, obj.at)) continue;
    const ObjectSpec& o = *st.object_spec[i];
    if (reported == &o) continue;
    reported = &o;
    const Object& parent = st.wc.objects[obj.parent];
    const double* values = &st.wc.values[parent.first_slot + kFirstAttributeSlot];
    // What it has, as the type names them: a repeated frame as its pattern and ranges.
    std::vector<std::string> frames, names;
    for (const FrameTemplate& f : st.wc.types[parent.type].templates.frames) {
      f.each(values, [&](const std::string& name, const Eigen::Isometry3d&) { names.push_back(name); });
      if (!f.repeat) {
        frames.push_back(f.name);
        continue;
      }
      std::vector<std::string> ranges;
      for (const RepeatTemplate::Counter& c : f.repeat->counters)
        ranges.push_back(fmt::format("{} 1 to {}", c.name, number_text(c.count.eval(values, NAN))));
      frames.push_back(fmt::format("{} ({})", f.name, fmt::join(ranges, ", ")));
    }
    st.diag.error(o.at.mark, fmt::format("'{}' is no named frame of {} (type '{}'){}; 'at' takes a frame the type names (or origin){}{}",
                                         obj.at, parent.name, st.wc.types[parent.type].name,
                                         frames.empty() ? ", which names none" : "; its frames: " + name_list(frames),
                                         obj.at == "top"    ? " (a top the type does not name is computed from its bounds, for reach; not for at)"
                                         : obj.at == "tool" ? " (a device's tool moves with its joints)"
                                                            : "",
                                         did_you_mean(obj.at, names)));
  }
}

/// Pass: parents, geomodel and colour.
void resolve_object_links(CompileState& st) {
  std::vector<std::string> names;
  for (size_t i = 0; i < st.wc.objects.size(); ++i) {
    Object& obj = st.wc.objects[i];
    const ObjectSpec& o = *st.object_spec[i];
    if (o.parent.present && !o.parent.null) {
      obj.parent = st.wc.find_object(o.parent.text);
      if (obj.parent < 0 && !st.is_unbuilt(o.parent.text)) {
        if (names.empty()) names = st.object_names();
        st.diag.error(o.parent.mark, fmt::format("unknown parent object '{}'{}", o.parent.text, did_you_mean(o.parent.text, names)));
      } else if (obj.parent == static_cast<int>(i)) {
        st.diag.error(o.parent.mark, fmt::format("object '{}' cannot be its own parent", obj.name));
        obj.parent = -1;
      }
    }
    if (o.at.present && !o.at.null) place_at(st, static_cast<int>(i), names);
    if (o.geomodel.present && !o.geomodel.null) {
      obj.geomodel = st.files.reference_path(st.spec.path, o.geomodel.text);
      if (std::string why = st.files.why_unreadable(obj.geomodel); !why.empty())
        st.diag.error(o.geomodel.mark, fmt::format("geomodel file '{}' {}", obj.geomodel, why));
    }
    const TypeTemplates& tt = st.wc.types[obj.type].templates;
    const bool own = o.color.present;
    const std::string& color = own ? o.color.text : tt.color;
    if (own ? !o.color.null : tt.has_color) {
      if (is_valid_color(color)) obj.color = color;
      else st.diag.error(own ? o.color.mark : tt.color_mark, fmt::format("expected a colour \"#RRGGBB\", found '{}'", color));
    }
  }
  // Parent cycles: walk up at most n steps; a cycle is reported once, at its first member.
  std::vector<char> in_reported_cycle(st.wc.objects.size(), 0);
  for (size_t i = 0; i < st.wc.objects.size(); ++i) {
    if (in_reported_cycle[i]) continue;
    std::vector<int> chain = {static_cast<int>(i)};
    for (int p = st.wc.objects[i].parent; p >= 0; p = st.wc.objects[p].parent) {
      if (p == static_cast<int>(i)) {
        std::vector<std::string> path;
        for (int c : chain) path.push_back(st.wc.objects[c].name);
        path.push_back(st.wc.objects[i].name);
        const ObjectSpec& o = *st.object_spec[i];  // `at` names the parent too
        for (int c : chain) in_reported_cycle[c] = 1;
        st.diag.error(o.parent.present ? o.parent.mark : o.at.mark,
                      fmt::format("parent chain ('parent' and 'at') forms a cycle: {}", fmt::join(path, " -> ")));
        break;
      }
      if (chain.size() > st.wc.objects.size()) break;  // a cycle further up, reported from its own members
      chain.push_back(p);
    }
  }
}

/// Pass: every object's values (written, or the type's defaults), then evaluation in dependency order.
void compile_values(CompileState& st) {
  for (size_t i = 0; i < st.wc.objects.size(); ++i) {
    const Object& obj = st.wc.objects[i];
    const ObjectSpec& o = *st.object_spec[i];
    const ObjectType& type = st.wc.types[obj.type];
    const std::array<int, 3>* index = o.array ? &st.array_index[i] : nullptr;
    ExprScope scope{-1, index};
    for (int d = 0; d < 3; ++d) {
      double offset = st.array_offset[i][d];
      if (o.location[d].present) assign(st, obj.first_slot + kLocationSlot + d, o.location[d], nullptr, Dim::Length, scope,
                                        kPoseSlotNames[kLocationSlot + d], offset);
      else st.wc.values[obj.first_slot + kLocationSlot + d] = offset;
      if (o.orientation[d].present)
        assign(st, obj.first_slot + kOrientationSlot + d, o.orientation[d], nullptr, Dim::Angle, scope, kPoseSlotNames[kOrientationSlot + d]);
    }
    std::vector<bool> given(type.attributes.size(), false);
    for (const AttrValue& v : o.attributes) {
      int a = type.find_attribute(v.name);
      if (a < 0) {
        std::vector<std::string> names(kObjectKeys.begin(), kObjectKeys.end());
        for (const AttributeDef& def : type.attributes) names.push_back(def.name);
        // Report once per written object, not once per array instance.
        if (i == 0 || st.object_spec[i - 1] != &o)
          st.diag.error(v.key_mark, fmt::format("type '{}' has no attribute '{}'{}", type.name, v.name, did_you_mean(v.name, names)));
        continue;
      }
      given[a] = true;
      const AttributeDef& def = type.attributes[a];
      size_t errors = st.diag.count();
      assign(st, obj.first_slot + kFirstAttributeSlot + a, v.value, &def, def.dim, scope,
             fmt::format("attribute '{}' of '{}'", def.name, obj.name));
      if (st.diag.count() > errors) st.slot_failed[obj.first_slot + kFirstAttributeSlot + a] = true;
    }
    for (size_t a = 0; a < type.attributes.size(); ++a) {
      if (given[a]) continue;
      const AttributeDef& def = type.attributes[a];
      if (!def.default_value.present || def.default_value.null) {
        if (i == 0 || st.object_spec[i - 1] != &o)
          st.diag.error(o.mark, fmt::format("object '{}' (a {}) needs a value for '{}', which has no default", obj.name,
                                            type.name, def.name));
        st.slot_failed[obj.first_slot + kFirstAttributeSlot + a] = true;
        continue;
      }
      // Type defaults may use the object's other attributes by their bare names.
      assign(st, obj.first_slot + kFirstAttributeSlot + a, def.default_value, &def, def.dim,
             ExprScope{static_cast<int>(i), index}, fmt::format("the default of '{}' in type '{}'", def.name, type.name));
    }
    if (st.diag.full()) return;
  }
  st.evaluate_pending();
}

/// A length beyond kMaxLengthSi (a location 1e155 m away, a drum 1e9 m high): an error naming the limit.
void check_length(CompileState& st, uint32_t slot, SourceMark mark, std::string_view what, std::string_view object) {
  double v = st.wc.values[slot];
  if (std::abs(v) <= kMaxLengthSi) return;
  st.diag.error(mark, fmt::format("{} of '{}' is {} m, beyond the {:g} m (1000 km) sscs places and sizes things within",
                                  what, object, number_text(v), kMaxLengthSi));
  st.slot_failed[slot] = true;
}

/// The rules of an object's type (`requires:`), and the copies its repeated geometry and frames
/// make: whole counts within the limit (an attribute's min and max usually see to it; an
/// expression may not).
void check_type_rules(CompileState& st, int o) {
  const Object& obj = st.wc.objects[o];
  const ObjectType& type = st.wc.types[obj.type];
  for (size_t a = 0; a < type.attributes.size(); ++a)
    if (st.slot_failed[obj.first_slot + kFirstAttributeSlot + a]) return;  // reported
  const double* values = &st.wc.values[obj.first_slot + kFirstAttributeSlot];
  auto check = [&](const RepeatTemplate* r, std::string_view what) {
    if (!r) return;
    if (std::string why = r->problem(values); !why.empty())
      st.diag.error(obj.mark, fmt::format("{} of '{}' (type '{}'): {}", what, obj.name, type.name, why));
  };
  const TypeTemplates& tt = type.templates;
  // The type's own rules first: a broken one explains what a count or a size then does.
  for (const RuleTemplate& rule : tt.rules) {
    const double held = rule.condition.eval(values, NAN);
    if (std::isnan(held))
      st.diag.error(obj.mark, fmt::format("'{}' (type '{}'): the rule '{}' of type '{}' cannot be evaluated for it", obj.name, type.name,
                                          rule.condition.text, rule.type));
    else if (held == 0)
      st.diag.error(obj.mark, fmt::format("'{}' (type '{}'): {}; the rule '{}' of type '{}' does not hold", obj.name, type.name,
                                          rule.message, rule.condition.text, rule.type));
  }
  const size_t before = st.diag.count();
  for (const ShapeTemplate& s : tt.geometry) check(s.repeat.get(), "a repeated shape");
  for (const FrameTemplate& f : tt.frames) check(f.repeat.get(), fmt::format("frame '{}'", f.name));
  if (tt.device)
    for (const PartTemplate& p : tt.device->parts)
      for (const ShapeTemplate& s : p.shapes) check(s.repeat.get(), fmt::format("a repeated shape of part '{}'", p.name));
  if (st.diag.count() != before) return;
  // Two frames of one name (`s{a}{b}` makes s111 twice; `slot_2` beside `slot_{k}`): `at` and
  // reach would take one and the listing show the other.
  std::map<std::string, std::string> seen;  // name -> the frame (pattern) that made it
  for (const FrameTemplate& f : tt.frames) {
    bool reported = false;
    f.each(values, [&](const std::string& name, const Eigen::Isometry3d&) {
      auto [it, fresh] = seen.emplace(name, f.name);
      if (fresh || reported) return;
      reported = true;
      st.diag.error(obj.mark, fmt::format("'{}' (type '{}') has two frames named '{}' (from '{}' and '{}'): frame names must differ", obj.name,
                                          type.name, name, it->second, f.name));
    });
  }
}

/// Pass: every value is a valid instance of its type (integers, min/max), and lengths and
/// locations lie within kMaxLengthSi.
void check_values(CompileState& st) {
  for (size_t i = 0; i < st.wc.objects.size() && !st.diag.full(); ++i) {
    const Object& obj = st.wc.objects[i];
    const ObjectType& type = st.wc.types[obj.type];
    const ObjectSpec& o = *st.object_spec[i];
    const size_t errors_before = st.diag.count();
    for (int d = 0; d < 3; ++d) {
      check_length(st, obj.first_slot + kLocationSlot + d, o.location[d].present ? o.location[d].mark : o.mark, kPoseSlotNames[kLocationSlot + d], obj.name);
      // An angle of 1e300 degrees is a rotation no double can reduce to a turn: a limit, like lengths.
      const uint32_t slot = obj.first_slot + kOrientationSlot + d;
      if (std::abs(st.wc.values[slot]) > kMaxAngleDeg * std::numbers::pi / 180) {
        st.diag.error(o.orientation[d].present ? o.orientation[d].mark : o.mark,
                      fmt::format("{} of '{}' is {} deg, beyond the ±{:g} deg sscs turns things by", kPoseSlotNames[kOrientationSlot + d], obj.name,
                                  number_text(st.wc.values[slot] * 180 / std::numbers::pi), kMaxAngleDeg));
        st.slot_failed[slot] = true;
      }
    }
    for (size_t a = 0; a < type.attributes.size(); ++a) {
      const AttributeDef& def = type.attributes[a];
      uint32_t slot = obj.first_slot + kFirstAttributeSlot + a;
      if (st.slot_failed[slot] || (st.slot_pending[slot] >= 0 && st.pending[st.slot_pending[slot]].state != 2)) continue;
      double v = st.wc.values[slot];
      auto written = std::find_if(o.attributes.begin(), o.attributes.end(), [&](const AttrValue& x) { return x.name == def.name; });
      SourceMark mark = written != o.attributes.end() ? written->value.mark : o.mark;
      std::string text = written != o.attributes.end() ? written->value.text : def.default_value.text;
      if (def.type == AttrType::Integer) {
        if (v < -2147483648.0 || v > 2147483647.0) {
          // The range the value may take: the type's, within what 32 bits hold.
          double lo = std::max(-2147483648.0, def.min_si.value_or(-2147483648.0));
          double hi = std::min(2147483647.0, def.max_si.value_or(2147483647.0));
          st.diag.error(mark, fmt::format("integer attribute '{}' of '{}' is {}, outside {} {:.0f} to {:.0f}", def.name, obj.name, text,
                                          def.min_si || def.max_si ? fmt::format("the range of type '{}':", type.name)
                                                                   : "the 32-bit range", lo, hi));
          continue;
        }
        if (v != std::floor(v)) {
          st.diag.error(mark, fmt::format("integer attribute '{}' of '{}' is {}, not a whole number", def.name, obj.name, v));
          continue;
        }
      }
      if (def.dim == Dim::Length) check_length(st, slot, mark, fmt::format("'{}'", def.name), obj.name);
      const double* values = &st.wc.values[obj.first_slot + kFirstAttributeSlot];
      const double lo = def.lower(values), hi = def.upper(values);
      if (std::isnan(lo) || std::isnan(hi) || lo > hi) {  // limits written as expressions
        st.diag.error(o.mark, fmt::format("joint '{}' of '{}' has the limits {} to {} (type '{}': min {}, max {}); the min must be a "
                                          "number at most the max", def.name, obj.name, with_unit(lo, def.dim), with_unit(hi, def.dim),
                                          type.name, def.min_expr.present ? def.min_expr.text : number_text(si_to_file(lo, def.dim)),
                                          def.max_expr.present ? def.max_expr.text : number_text(si_to_file(hi, def.dim))));
        continue;
      }
      if (auto in = within_bounds(v, lo, hi)) st.wc.values[slot] = *in;  // a bound copied from `sscs types` is the bound
      else {
        const ValueRef& bound = v < lo ? def.min_expr : def.max_expr;  // a limit written as an expression: say which
        st.diag.error(mark, fmt::format("'{}' of '{}' is {}, {} {} of type '{}'{}", def.name, obj.name, with_unit(v, def.dim),
                                        v < lo ? "below the min" : "above the max", with_unit(v < lo ? lo : hi, def.dim), type.name,
                                        bound.present ? fmt::format(" ({} for this object)", bound.text) : ""));
      }
    }
    if (st.diag.count() == errors_before) check_type_rules(st, static_cast<int>(i));  // else the rules repeat what was said
  }
}

}  // namespace

std::optional<Workcell> compile(const VaultSpec& spec, const VaultInputs& inputs, const CompileOptions& options, Sources& sources,
                                Diagnostics& diag) {
  CompileState st(spec, sources, diag, inputs.files);
  st.wc.name = spec.name;
  st.wc.path = spec.path;
  st.wc.description = spec.description;
  st.plugins = inputs.plugins;
  st.wc.plugin_files = st.plugins->files();
  st.wc.vault_plugin_dirs = inputs.vault_plugin_dirs;
  // The type library: reused, or built from its gathered type files (the templates of the types
  // the vault's objects use and those they extend, unless the library is to be reused).
  if (options.library) {
    st.wc.types = *options.library;
  } else if (inputs.library) {
    std::set<std::string> used;
    for (const ObjectSpec& o : spec.objects) used.insert(o.type);
    st.wc.types = build_library(*inputs.library, sources, diag, options.whole_library ? nullptr : &used);
  }
  std::vector<Scalar> overrides;
  compile_parameters(st, options, overrides);
  if (diag.has_errors()) return std::nullopt;
  // Objects whose type is unknown are left out and later passes go on, so one run reports the
  // errors of every object; references to left-out objects add no second error.
  expand_objects(st);
  resolve_object_links(st);
  compile_values(st);
  check_values(st);
  check_at_frames(st);
  if (!diag.full()) compile_constraints(st);
  for (const auto& [name, key] : spec.cameras)  // the vault's named views
    for (const CameraKey& k : compile_camera_keys({key}, st.wc, diag)) st.wc.cameras.emplace_back(name, k);
  if (diag.has_errors()) return std::nullopt;
  st.wc.texts.resize(st.wc.values.size());
  return std::move(st.wc);
}


}  // namespace sscs
