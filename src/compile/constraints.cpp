// Pass: constraints. Resolve references and selectors to slots and objects, check dimensions.
#include <algorithm>
#include <cmath>
#include <string_view>
#include <unordered_set>

#include <fmt/format.h>

#include "compile/state.h"
#include "compile/values.h"
#include "core/names.h"
#include "core/pose.h"
#include "core/selection_calls.h"

namespace sscs {

namespace {

bool looks_like_reference(std::string_view s) {
  if (s.empty()) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  });
}

/// A bound side: a number (maybe with a unit) or a reference.
std::optional<Operand> bound_operand(CompileState& st, const Scalar& s, std::string_view what) {
  if (!s.present) return std::nullopt;
  if (s.null || s.text.empty()) {
    st.diag.error(s.mark, fmt::format("expected a reference or a number for {}, found nothing", what));
    return std::nullopt;
  }
  std::string unknown;
  if (auto q = parse_quantity(s.text, &unknown)) {
    Operand op;
    op.constant_si = q->si;
    op.dim = q->has_unit ? q->dim : Dim::None;
    op.text = s.text;
    return op;
  }
  if (!unknown.empty()) {
    st.diag.error(s.mark, fmt::format("unknown unit '{}' in '{}' for {}; known units are: {}", unknown, s.text, what,
                                      known_units(Dim::None)));
    return std::nullopt;
  }
  if (!looks_like_reference(s.text)) {
    st.diag.error(s.mark, fmt::format("expected a reference (Object.attribute) or a number for {}, found '{}'; "
                                      "use an expr constraint for expressions", what, s.text));
    return std::nullopt;
  }
  return st.resolve_reference(s.text, mark_at(s, 0), {}, /*allow_bbox=*/true);
}

std::vector<int> select(CompileState& st, const SelectorSpec& sel, std::string_view what) {
  std::vector<int> out, removed;
  std::vector<std::string> names;
  // The items, a list's (`[A, B, !C]`, as aggregates write one) each with its own mark.
  std::vector<Scalar> items;
  for (const Scalar& item : sel.items)
    for (std::string_view piece : split_selector_list(item.text)) {
      Scalar one = item;
      one.text = std::string(piece);
      if (piece.data() != item.text.data()) {
        one.mark = mark_at(item, static_cast<size_t>(piece.data() - item.text.data()));
        one.quoted = false;
      }
      items.push_back(std::move(one));
    }
  for (const Scalar& item : items) {
    // `!SEL` removes what SEL selects (`["*", "!type:keepout_zone"]`).
    const bool remove = item.text.starts_with('!');
    const std::string t = remove ? item.text.substr(1) : item.text;
    if (auto found = st.wc.select(t)) {
      (remove ? removed : out).insert((remove ? removed : out).end(), found->begin(), found->end());
    } else if (st.may_select_unbuilt(t)) {
      // follows from the error that dropped it
    } else if (t.starts_with("at:")) {
      if (names.empty()) names = st.object_names();
      const std::string object = t.substr(3, t.find('.') == std::string::npos ? std::string::npos : t.find('.') - 3);
      st.diag.error(item.mark, t.find('.') == std::string::npos
                                   ? fmt::format("expected at:OBJECT.FRAME (globs allowed, as at:Row_1.slot_*_5_*), found '{}'", t)
                                   : fmt::format("unknown object '{}' in selector '{}'{}", object, t, did_you_mean(object, names)));
    } else if (t.starts_with("type:")) {
      std::string type = t.substr(5);
      std::vector<std::string> types;
      for (const ObjectType& x : st.wc.types) types.push_back(x.name);
      st.diag.error(item.mark, fmt::format("unknown type '{}' in selector{}", type, did_you_mean(type, types)));
    } else {
      if (names.empty()) names = st.object_names();
      st.diag.error(item.mark, fmt::format("unknown object '{}' in selector{}", t, did_you_mean(t, names)));
    }
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  std::erase_if(out, [&](int o) { return std::find(removed.begin(), removed.end(), o) != removed.end(); });
  if (out.empty() && !sel.allow_empty && !st.diag.has_errors())
    st.diag.error(sel.mark, fmt::format("{} selects no objects (add allow_empty: true if that is intended)", what));
  return out;
}

/// A plugin's `attributes` entry as the references it stands for. A reference stands for itself;
/// one whose object part is a selector (`Drum_*.height`, `type:drum.bbox.min.z`) for that
/// reference of each selected object, in the selector's order; and `X.bbox` for X's six
/// bounding-box values (min x, y, z, then max x, y, z).
std::vector<Scalar> plugin_references(CompileState& st, const Scalar& s) {
  size_t dot = s.text.find('.');
  std::string head = s.text.substr(0, dot), rest = dot == std::string::npos ? "" : s.text.substr(dot);
  std::vector<std::string> objects;
  if (head.starts_with("type:") || head.find_first_of("*?") != std::string::npos) {
    SelectorSpec sel;
    sel.items.push_back(s);
    sel.items.back().text = head;
    sel.mark = s.mark;
    sel.allow_empty = true;  // reported here, without select()'s allow_empty hint (plugins have none)
    size_t before = st.diag.count();
    for (int o : select(st, sel, "")) objects.push_back(st.wc.objects[o].name);
    if (objects.empty() && st.diag.count() == before)
      st.diag.error(s.mark, fmt::format("the plugin attribute '{}' selects no objects", s.text));
  } else {
    objects.push_back(head);
  }
  std::vector<std::string> tails = {rest};
  if (rest == ".bbox") tails = {".bbox.min.x", ".bbox.min.y", ".bbox.min.z", ".bbox.max.x", ".bbox.max.y", ".bbox.max.z"};
  std::vector<Scalar> out;
  for (const std::string& o : objects)
    for (const std::string& tail : tails) {
      out.push_back(s);
      out.back().text = o + tail;
    }
  return out;
}

int object_ref(CompileState& st, const Scalar& s, std::string_view what) {
  if (!s.present || s.null) return -1;
  int o = st.wc.find_object(s.text);
  if (o < 0 && !st.is_unbuilt(s.text)) st.diag.error(s.mark, fmt::format("unknown object '{}' for {}{}", s.text, what, did_you_mean(s.text, st.object_names())));
  return o;
}

/// A side of a clearance pair: one object by name (with "did you mean"), or a selector.
std::vector<int> pair_side(CompileState& st, const SelectorSpec& sel, std::string_view what) {
  bool one_name = sel.items.size() == 1 && !sel.items[0].text.starts_with("type:") &&
                  sel.items[0].text.find_first_of("*?") == std::string::npos;
  if (!one_name) return select(st, sel, what);
  int o = object_ref(st, sel.items[0], "clearance");
  return o < 0 ? std::vector<int>{} : std::vector<int>{o};
}

/// The largest tolerance of a spatial check (m): more would pass real violations unseen (an
/// allowance is a clearance's or inside's `min`, and shows in the margin).
constexpr double kMaxSpatialEpsSi = 0.1;

void spatial_eps(CompileState& st, const Scalar& eps, SpatialCheck& sc) {
  if (!eps.present) return;
  sc.eps_si = st.number_now(eps, Dim::Length, "eps").value_or(sc.eps_si);
  if (sc.eps_si < 0) st.diag.error(eps.mark, "eps must not be negative");
  if (sc.eps_si > kMaxSpatialEpsSi)
    st.diag.error(eps.mark, fmt::format("eps of a spatial check is at most {:g} m, found {} m: a larger tolerance would pass "
                                        "real violations unseen (an allowance belongs in min)", kMaxSpatialEpsSi, number_text(sc.eps_si)));
}

/// `min` of a clearance or inside: a distance kept, never negative (that would pass overlaps).
double spatial_min(CompileState& st, const Scalar& min, const char* what) {
  double v = st.number_now(min, Dim::Length, what).value_or(0);
  if (v < 0)
    st.diag.error(min.mark, fmt::format("{} must not be negative, found {} m: it is a distance kept, and a negative one would "
                                        "pass overlapping objects", what, number_text(v)));
  return v;
}

/// `faces:` of an inside constraint: all (default), walls, or a list of x- x+ y- y+ z- z+.
uint8_t inside_faces(CompileState& st, const InsideSpec& in) {
  static constexpr std::pair<std::string_view, uint8_t> kFaces[] = {
      {"x-", SpatialCheck::XMin}, {"x+", SpatialCheck::XMax}, {"y-", SpatialCheck::YMin},
      {"y+", SpatialCheck::YMax}, {"z-", SpatialCheck::ZMin}, {"z+", SpatialCheck::ZMax}};
  if (in.faces.empty()) return SpatialCheck::All;
  if (in.faces.size() == 1 && in.faces[0].text == "all") return SpatialCheck::All;
  if (in.faces.size() == 1 && in.faces[0].text == "walls") return SpatialCheck::Walls;
  uint8_t mask = 0;
  for (const Scalar& f : in.faces) {
    auto it = std::find_if(std::begin(kFaces), std::end(kFaces), [&](const auto& k) { return k.first == f.text; });
    if (it == std::end(kFaces)) {
      st.diag.error(f.mark, fmt::format("expected all, walls, or a list of x- x+ y- y+ z- z+ for inside faces, found '{}'{}", f.text,
                                        did_you_mean(f.text, {"walls", "all", "x-", "x+", "y-", "y+", "z-", "z+"})));
      continue;
    }
    if (mask & it->second) st.diag.error(f.mark, fmt::format("face '{}' is listed twice", f.text));
    mask |= it->second;
  }
  return mask;
}

void add_subjects(std::vector<int>& subjects, const std::vector<Operand>& ops) {
  for (const Operand& op : ops)
    if (op.object >= 0) subjects.push_back(op.object);
}

void finish_subjects(std::vector<int>& subjects) {
  std::sort(subjects.begin(), subjects.end());
  subjects.erase(std::unique(subjects.begin(), subjects.end()), subjects.end());
}


/// An expr constraint's text with its aggregate calls (count, sum, min, max, avg over selectors)
/// replaced by variables, and the operand each call stands for.
struct ExprSource {
  const Scalar& whole;  ///< as written
  RewrittenExpression rewritten;
  std::vector<Operand> calls;
};

/// Resolves the names of `expr` (parsed from a piece of the rewritten text starting at `offset`):
/// a call's variable to its aggregate, anything else as a reference, marked where it was written.
bool resolve_expr_inputs(CompileState& st, const Expression& expr, const ExprSource& src, size_t offset, std::vector<Operand>& out) {
  bool ok = true;
  out.clear();
  for (const std::string& n : expr.names()) {
    if (int call = RewrittenExpression::call_index(n); call >= 0 && call < static_cast<int>(src.calls.size())) {
      out.push_back(src.calls[call]);
      continue;
    }
    size_t pos = src.rewritten.text.find(n, offset);
    auto op = st.resolve_reference(n, mark_at(src.whole, pos == std::string::npos ? 0 : src.rewritten.original(pos)), {},
                                   /*allow_bbox=*/true);
    if (!op) {
      ok = false;
      continue;
    }
    out.push_back(*op);
  }
  return ok;
}

/// The operand of an aggregate call: each selected object's attribute (SI), reduced at check time.
std::optional<Operand> aggregate_operand(CompileState& st, const SelectionCall& call, const Scalar& whole, bool allow_empty) {
  SelectorSpec sel;
  sel.items.push_back(whole);
  sel.items.back().text = call.selector;
  sel.items.back().mark = mark_at(whole, call.arg_position);
  sel.items.back().quoted = false;  // its mark is at the selector itself
  sel.mark = sel.items.back().mark;
  sel.allow_empty = true;  // reported below, naming the call
  size_t errors = st.diag.count();
  std::vector<int> objects = select(st, sel, "");
  if (st.diag.count() != errors) return std::nullopt;
  const char* name = selection_call_name(call.kind);
  if (objects.empty() && !allow_empty) {
    if (st.may_select_unbuilt(call.selector)) return std::nullopt;  // follows from an earlier error
    st.diag.error(sel.mark, fmt::format("{}({}) selects no objects (add allow_empty: true beside expr if that is intended)", name,
                                        call.kind == SelectionCall::Kind::Count ? call.selector : call.selector + "." + call.attribute));
    return std::nullopt;
  }
  Operand op;
  op.kind = Operand::Kind::Aggregate;
  op.aggregate = static_cast<uint8_t>(call.kind);
  op.text = call.kind == SelectionCall::Kind::Count ? fmt::format("count({})", call.selector)
                                                     : fmt::format("{}({}.{})", name, call.selector, call.attribute);
  auto members = std::make_shared<std::vector<Operand>>();
  for (int o : objects) {
    if (call.kind == SelectionCall::Kind::Count) {
      members->push_back(Operand{});
      members->back().object = o;
      continue;
    }
    auto m = st.resolve_reference(st.wc.objects[o].name + "." + call.attribute, sel.mark, {}, /*allow_bbox=*/true);
    if (!m) return std::nullopt;
    if (op.dim == Dim::None) op.dim = m->dim;
    members->push_back(*m);
  }
  op.members = std::move(members);
  return op;
}

std::optional<ExprCheck::Side> compile_side(CompileState& st, const std::string& text, const ExprSource& src) {
  Expression::Error err;
  auto e = Expression::parse(text, &err);
  if (!e) return std::nullopt;
  ExprCheck::Side side;
  side.expr = std::make_shared<const Expression>(std::move(*e));
  size_t offset = src.rewritten.text.find(text);
  if (!resolve_expr_inputs(st, *side.expr, src, offset == std::string::npos ? 0 : offset, side.inputs)) return std::nullopt;
  return side;
}

std::optional<ExprCheck::MarginNode> compile_margin(CompileState& st, const MarginTree& tree, const ExprSource& src) {
  ExprCheck::MarginNode node;
  node.op = tree.op;
  if (tree.op == MarginTree::Op::Or || tree.op == MarginTree::Op::And || tree.op == MarginTree::Op::Not) {
    for (const MarginTree& c : tree.children) {
      auto child = compile_margin(st, c, src);
      if (!child) return std::nullopt;
      node.children.push_back(std::move(*child));
    }
    node.dim = node.children.front().dim;
    for (const auto& child : node.children)
      if (child.dim != node.dim) node.dim = Dim::None;
    return node;
  }
  auto lhs = compile_side(st, tree.lhs, src);
  auto rhs = compile_side(st, tree.rhs, src);
  if (!lhs || !rhs) return std::nullopt;
  node.lhs = std::move(*lhs);
  node.rhs = std::move(*rhs);
  // The sides agree (checked before); a plain number takes the other side's dimension.
  for (const ExprCheck::Side* side : {&node.lhs, &node.rhs})
    if (auto d = expression_dim(*side->expr, side->inputs); d && *d != Dim::Fraction) {
      node.dim = *d;
      break;
    }
  return node;
}

void compile_bound(CompileState& st, const BoundSpec& b, Constraint& c) {
  auto lhs = bound_operand(st, b.lhs, "the bound's lhs");
  auto rhs = bound_operand(st, b.rhs, "the bound's rhs");
  if (!lhs || !rhs) return;
  if (lhs->dim != Dim::None && rhs->dim != Dim::None && lhs->dim != rhs->dim) {
    st.diag.error(b.rhs.mark, fmt::format("bound compares {} '{}' with {} '{}'", dim_name(lhs->dim), b.lhs.text,
                                         dim_name(rhs->dim), b.rhs.text));
    return;
  }
  BoundCheck check;
  check.dim = lhs->dim != Dim::None ? lhs->dim : rhs->dim;
  // Plain numbers are in the file unit of the other side's dimension ("90" beside an angle is 90 deg).
  for (Operand* op : {&*lhs, &*rhs})
    if (op->kind == Operand::Kind::Constant && op->dim == Dim::None) {
      op->constant_si *= file_unit_to_si(check.dim);
      op->dim = check.dim;
    }
  check.lhs = *lhs;
  check.rhs = *rhs;
  check.op = b.op;
  if (b.lhs_tol.present)
    check.lhs_tol_si = st.number_now(b.lhs_tol, check.dim, "lhs_tol").value_or(0);
  if (b.rhs_tol.present)
    check.rhs_tol_si = st.number_now(b.rhs_tol, check.dim, "rhs_tol").value_or(0);
  if (b.eps.present) {
    check.eps_si = st.number_now(b.eps, check.dim, "eps").value_or(1e-9);
    if (check.eps_si < 0) st.diag.error(b.eps.mark, "eps must not be negative");
    // As large as any size sscs takes (1e6 in SI units): beyond it every bound would hold.
    if (check.eps_si > kMaxLengthSi)
      st.diag.error(b.eps.mark, fmt::format("eps is at most {:g} (SI units), found {}: every comparison would hold", kMaxLengthSi,
                                            number_text(check.eps_si)));
  }
  add_subjects(c.subjects, {check.lhs, check.rhs});
  c.body = std::move(check);
}

void compile_expr(CompileState& st, const ExprSpec& e, Constraint& c) {
  using K = SelectionCall::Kind;
  if (e.expr.null || e.expr.text.empty()) {
    st.diag.error(e.expr.mark, "expected a boolean expression for expr, found nothing");
    return;
  }
  Expression::Error err;
  auto rewritten = rewrite_selection_calls(e.expr.text, {K::Count, K::Sum, K::Min, K::Max, K::Avg}, &err);
  if (!rewritten) {
    st.diag.error(mark_at(e.expr, err.position), fmt::format("{} in the expr '{}'", err.message, e.expr.text));
    return;
  }
  ExprSource src{e.expr, std::move(*rewritten), {}};
  std::shared_ptr<const Expression> expr;
  if (src.rewritten.calls.empty()) {
    expr = st.parse_expression(e.expr, "an expr constraint");  // shared by constraints of the same text
  } else {
    auto parsed = Expression::parse(src.rewritten.text, &err);
    if (!parsed)
      st.diag.error(mark_at(e.expr, src.rewritten.original(err.position)),
                    fmt::format("cannot read '{}' as an expression for an expr constraint: {}", e.expr.text, without_position(err.message)));
    else
      expr = std::make_shared<const Expression>(std::move(*parsed));
  }
  if (!expr) return;
  for (const SelectionCall& call : src.rewritten.calls) {
    auto op = aggregate_operand(st, call, e.expr, e.allow_empty);
    if (!op) return;
    for (const Operand& m : *op->members) c.subjects.push_back(m.object);
    src.calls.push_back(std::move(*op));
  }
  ExprCheck check;
  check.text = e.expr.text;
  check.expr = expr;
  if (!resolve_expr_inputs(st, *expr, src, 0, check.inputs)) return;
  if (!check_expression_dimensions(*expr, check.inputs, e.expr, Dim::None, "an expr constraint", st.diag,
                                   [&](size_t pos) { return src.rewritten.original(pos); }))
    return;
  add_subjects(c.subjects, check.inputs);
  if (auto tree = split_for_margin(src.rewritten.text)) check.margin = compile_margin(st, *tree, src);
  c.body = std::move(check);
}

}  // namespace

namespace {

/// A pose a constraint gives ({xyz, rpy}): each number may be a parameter or an expression, as
/// anywhere a file gives a number (a reach offset of `[0, 0, Drum_1.height]`).
Eigen::Isometry3d pose_now(CompileState& st, const PoseSpec& p, std::string_view what) {
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) {
    if (p.xyz[k].present) xyz[k] = st.number_now(p.xyz[k], Dim::Length, fmt::format("{} xyz", what)).value_or(0);
    if (p.rpy[k].present) rpy[k] = st.number_now(p.rpy[k], Dim::Angle, fmt::format("{} rpy", what)).value_or(0);
  }
  return make_pose(xyz, rpy);
}

/// reach's `carrying`: an object the device can hold, not one of its targets; -1 when absent
/// or wrong (an input error).
int carried_load(CompileState& st, const ReachSpec& r, const ReachCheck& rc) {
  if (!r.carrying.present || r.carrying.null) return -1;
  const std::string& text = r.carrying.text;
  if (text.empty() || text.find_first_of("*?") != std::string::npos || text.starts_with("type:") || text.starts_with("at:") ||
      (text.find('.') != std::string::npos && st.wc.find_object(text.substr(0, text.find('.'))) >= 0)) {
    st.diag.error(r.carrying.mark, fmt::format("reach carrying: expected the name of one object, found '{}'{}", text,
                                               text.find('.') != std::string::npos ? " (a frame is not an object: name the object)"
                                               : text.empty()                      ? ""
                                                                                   : " (a selector: carrying holds one object)"));
    return -1;
  }
  const int o = object_ref(st, r.carrying, "reach carrying");
  if (o < 0) return -1;
  const Object& load = st.wc.objects[o];
  const ObjectType& type = st.wc.types[load.type];
  std::string why;
  if (o == rc.device) why = "it is the device itself";
  else if (type.device) why = fmt::format("it is a device ({})", type.name);
  else if (type.container) why = fmt::format("it is a container ({}): it holds objects, a tool does not hold it", type.name);
  else if (rc.device >= 0 && st.wc.related(rc.device, o)) why = fmt::format("{} stands on it (its parent chain)", st.wc.objects[rc.device].name);
  else if (std::any_of(rc.targets.begin(), rc.targets.end(), [&](const ReachCheck::Target& t) { return t.object == o; }))
    why = "it is one of the targets (carrying places it at each target)";
  else if (auto rider = std::find_if(rc.targets.begin(), rc.targets.end(), [&](const ReachCheck::Target& t) {
             for (int up = t.object >= 0 ? st.wc.objects[t.object].parent : -1; up >= 0; up = st.wc.objects[up].parent)
               if (up == o) return true;
             return false;
           });
           rider != rc.targets.end())
    why = fmt::format("target {} stands on it (its parent chain), and would be carried with it", rider->text);
  if (why.empty()) return o;
  st.diag.error(r.carrying.mark, fmt::format("reach carrying '{}': {}", r.carrying.text, why));
  return -1;
}

ReachCheck compile_reach(CompileState& st, const ReachSpec& r) {
  ReachCheck rc;
  rc.device = object_ref(st, r.device, "reach device");
  if (rc.device >= 0 && !st.wc.types[st.wc.objects[rc.device].type].device) {
    st.diag.error(r.device.mark, fmt::format("reach device '{}' is a {}, not a device", r.device.text,
                                              st.wc.types[st.wc.objects[rc.device].type].name));
    rc.device = -1;
  }
  std::string default_frame = r.frame.present && !r.frame.null ? r.frame.text : "origin";
  // `Drum_3.top` and `Drum_*.top` name a frame; other items use `frame:`.
  SelectorSpec plain = r.targets;
  plain.items.clear();
  std::vector<std::pair<Scalar, std::string>> framed;
  std::vector<SourceMark> frame_marks;
  for (const Scalar& item : r.targets.items) {
    auto dot = item.text.rfind('.');
    // `at:Row_1.top_*` is a selector with one dot of its own; `at:Row_1.top_*.top` names a frame.
    const bool at_selector = item.text.starts_with("at:") || item.text.starts_with("!at:");
    if (at_selector && item.text.find('.') == dot) dot = std::string::npos;
    if (dot == std::string::npos || item.text.starts_with("type:")) {
      plain.items.push_back(item);
      continue;
    }
    Scalar sel = item;
    sel.text = item.text.substr(0, dot);
    framed.emplace_back(sel, item.text.substr(dot + 1));
    frame_marks.push_back(mark_at(item, dot + 1));
  }
  auto add = [&](const std::vector<int>& objects, const std::string& frame, SourceMark where) {
    for (int o : objects) {
      if (o == rc.device) continue;  // "*" selects the device too
      auto names = st.wc.frame_names(o);
      // A glob over frames (`Row_*.slot_3_*`): every frame of the object it matches, at least one.
      if (frame.find_first_of("*?") != std::string::npos) {
        size_t matched = 0;
        for (const std::string& name : names)
          if (glob_match(frame, name)) {
            rc.targets.push_back({o, name, Eigen::Isometry3d::Identity(), st.wc.objects[o].name + "." + name});
            ++matched;
          }
        if (matched == 0) {
          st.diag.error(where, fmt::format("'{}' matches no frame of {} ({}); its frames: {}", frame, st.wc.objects[o].name,
                                           st.wc.types[st.wc.objects[o].type].name, name_list(names)));
          return;
        }
        continue;
      }
      if (std::find(names.begin(), names.end(), frame) == names.end()) {
        st.diag.error(where, fmt::format("'{}' is not a frame of {} ({}); its frames: {}{}", frame,
                                              st.wc.objects[o].name, st.wc.types[st.wc.objects[o].type].name,
                                              name_list(names), did_you_mean(frame, names)));
        return;
      }
      rc.targets.push_back({o, frame, Eigen::Isometry3d::Identity(),
                            frame == "origin" ? st.wc.objects[o].name : st.wc.objects[o].name + "." + frame});
    }
  };
  bool any = !r.poses.empty();
  if (!plain.items.empty()) {
    SelectorSpec sel = plain;
    sel.allow_empty = true;
    auto objects = select(st, sel, "reach targets");
    any = any || !objects.empty();
    add(objects, default_frame, r.frame.present ? r.frame.mark : plain.items.front().mark);
  }
  for (size_t k = 0; k < framed.size(); ++k) {
    const auto& [sel_text, frame] = framed[k];
    SelectorSpec sel{{sel_text}, sel_text.mark, true};
    auto objects = select(st, sel, "reach targets");
    any = any || !objects.empty();
    add(objects, frame, frame_marks[k]);
  }
  if (!any && !r.targets.allow_empty && !st.diag.has_errors())
    st.diag.error(r.targets.mark, "reach targets selects no objects (add allow_empty: true if that is intended)");
  for (const auto& [pose, mark] : r.poses) {
    ReachCheck::Target t;
    t.pose = pose_now(st, pose, "reach target");
    const Eigen::Vector3d& p = t.pose.translation();
    t.text = fmt::format("[{:g}, {:g}, {:g}]", stable(si_to_file(p.x(), Dim::Length)), stable(si_to_file(p.y(), Dim::Length)),
                         stable(si_to_file(p.z(), Dim::Length)));
    rc.targets.push_back(std::move(t));
  }
  rc.match_orientation = r.match_orientation;
  rc.offset = pose_now(st, r.offset, "reach offset");
  if (r.position_tol.present) rc.position_tol_si = st.number_now(r.position_tol, Dim::Length, "position_tol").value_or(1e-3);
  if (r.angle_tol.present) rc.angle_tol_si = st.number_now(r.angle_tol, Dim::Angle, "angle_tol").value_or(rc.angle_tol_si);
  for (auto [v, s] : {std::pair{rc.position_tol_si, &r.position_tol}, std::pair{rc.angle_tol_si, &r.angle_tol}})
    if (!(v > 0)) st.diag.error(s->mark, fmt::format("{} must be positive, found {}", s == &r.position_tol ? "position_tol" : "angle_tol", s->text));
  rc.carrying = carried_load(st, r, rc);
  if (rc.carrying >= 0)
    for (size_t o = 0; o < st.wc.objects.size(); ++o)
      for (int up = st.wc.objects[o].parent; up >= 0; up = st.wc.objects[up].parent)
        if (up == rc.carrying) {
          rc.carried_with.push_back(static_cast<int>(o));
          break;
        }
  return rc;
}

}  // namespace

void compile_constraints(CompileState& st) {
  // Views into the spec, which outlives this pass; a hash set, as vaults hold 200,000 constraints.
  std::unordered_set<std::string_view> seen;
  seen.reserve(st.spec.constraints.size());
  st.wc.constraints.reserve(st.spec.constraints.size());
  static_assert(std::variant_size_v<ConstraintKind> == 7, "every constraint kind has its branch below");
  for (const ConstraintSpec& spec : st.spec.constraints) {
    if (!seen.insert(spec.name).second)
      st.diag.error(spec.mark, fmt::format("constraint name '{}' is used twice", spec.name));
    Constraint c;
    c.name = spec.name;
    c.description = spec.description;
    c.mark = spec.mark;
    c.severity = spec.severity;
    c.kind = constraint_kind_name(spec.kind);
    if (auto* b = std::get_if<BoundSpec>(&spec.kind)) {
      compile_bound(st, *b, c);
    } else if (auto* e = std::get_if<ExprSpec>(&spec.kind)) {
      compile_expr(st, *e, c);
    } else if (auto* pbox = std::get_if<Boxed<PluginSpec>>(&spec.kind)) {
      auto* p = &**pbox;
      PluginCheck pc;
      size_t given = 0, errors_before = st.diag.count();
      for (const Scalar& written : p->attributes)
        for (const Scalar& ref : plugin_references(st, written)) {
          ++given;
          if (auto op = bound_operand(st, ref, "a plugin attribute")) {
            if (op->object >= 0) c.subjects.push_back(op->object);
            pc.inputs.push_back(std::move(*op));
          }
        }
      finish_subjects(c.subjects);
      pc.args_json = p->args.is_null() ? "{}" : p->args.dump();
      const ConstraintClass* cls = st.plugins ? st.plugins->find(p->cls.text) : nullptr;
      if (cls) {
        pc.class_name = cls->name;
        pc.evaluate = [plugins = st.plugins, cls, args = pc.args_json](const std::string& constraint, const std::vector<sscs_value>& values) {
          return plugins->check(*cls, constraint, values, args);
        };
      }
      if (!cls) {
        std::vector<std::string> names;
        if (st.plugins)
          for (const ConstraintClass& k : st.plugins->classes()) names.push_back(k.name);
        st.diag.error(p->cls.mark, fmt::format("no loaded plugin provides constraint class '{}'{}{}", p->cls.text,
                                               did_you_mean(p->cls.text, names),
                                               names.empty() ? " (no plugins are loaded: pass --plugins DIR)" : ""));
      } else if (st.diag.count() == errors_before && (given < cls->min_values || given > cls->max_values)) {
        st.diag.error(p->cls.mark, fmt::format("constraint class '{}' takes {} attributes, found {}", p->cls.text,
                                               cls->min_values == cls->max_values ? fmt::format("{}", cls->min_values)
                                               : cls->max_values == SIZE_MAX ? fmt::format("at least {}", cls->min_values)
                                               : fmt::format("{} to {}", cls->min_values, cls->max_values),
                                               given));
      }
      c.body = std::move(pc);
    } else if (auto* clbox = std::get_if<Boxed<ClearanceSpec>>(&spec.kind)) {
      auto* cl = &**clbox;
      SpatialCheck sc;
      if (cl->objects) {
        sc.kind = SpatialCheck::Kind::ClearanceSet;
        sc.objects = select(st, *cl->objects, "clearance objects");
      } else if (cl->a && cl->b) {
        sc.kind = SpatialCheck::Kind::ClearancePair;
        sc.objects = pair_side(st, *cl->a, "clearance a");
        sc.others = pair_side(st, *cl->b, "clearance b");
      }
      if (cl->min.present) sc.min_si = spatial_min(st, cl->min, "clearance min");
      spatial_eps(st, cl->eps, sc);
      c.subjects = sc.objects;
      c.subjects.insert(c.subjects.end(), sc.others.begin(), sc.others.end());
      c.body = std::move(sc);
    } else if (auto* nbox = std::get_if<Boxed<NoOverlapSpec>>(&spec.kind)) {
      SpatialCheck sc;
      sc.kind = SpatialCheck::Kind::NoOverlap;
      sc.objects = select(st, (*nbox)->objects, "no_overlap objects");
      spatial_eps(st, (*nbox)->eps, sc);
      c.subjects = sc.objects;
      c.body = std::move(sc);
    } else if (auto* inbox = std::get_if<Boxed<InsideSpec>>(&spec.kind)) {
      auto* in = &**inbox;
      SpatialCheck sc;
      sc.kind = SpatialCheck::Kind::Inside;
      sc.objects = select(st, in->objects, "inside objects");
      sc.container = object_ref(st, in->container, "inside container");
      // The container is never checked against itself.
      sc.objects.erase(std::remove(sc.objects.begin(), sc.objects.end(), sc.container), sc.objects.end());
      if (in->min.present) sc.min_si = spatial_min(st, in->min, "inside min");
      spatial_eps(st, in->eps, sc);
      sc.faces = inside_faces(st, *in);
      c.subjects = sc.objects;
      if (sc.container >= 0) c.subjects.push_back(sc.container);
      c.body = std::move(sc);
    } else if (auto* rbox = std::get_if<Boxed<ReachSpec>>(&spec.kind)) {
      ReachCheck rc = compile_reach(st, **rbox);
      if (rc.device >= 0) c.subjects.push_back(rc.device);
      for (const ReachCheck::Target& t : rc.targets)
        if (t.object >= 0) c.subjects.push_back(t.object);
      if (rc.carrying >= 0) c.subjects.push_back(rc.carrying);
      c.body = std::move(rc);
    }
    finish_subjects(c.subjects);
    st.wc.constraints.push_back(std::move(c));
    if (st.diag.full()) return;
  }
}

}  // namespace sscs
