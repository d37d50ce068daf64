// Checks a URDF's numbers element by element, as the URDF format defines them
// (http://wiki.ros.org/urdf/XML), before urdfdom reads the file.
#include "load/urdf_xml.h"

#include <charconv>
#include <algorithm>
#include <map>
#include <set>
#include <cmath>
#include <cstdlib>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tinyxml.h>

#include "core/files.h"
#include "load/load.h"

namespace sscs {

namespace {

/// What values an attribute may take.
enum class Range { Any, NotNegative, Unit };

class UrdfChecker {
 public:
  UrdfChecker(uint32_t file, Diagnostics& diag) : file_(file), diag_(diag) {}

  SourceMark mark(const TiXmlBase& at) const { return xml_mark(file_, at); }

  /// Attribute `name` of `e`: `count` finite numbers separated by spaces, in `range`; `required`
  /// says whether it may be absent. `what` names the numbers in messages ("lengths in m").
  void numbers(const TiXmlElement& e, const char* name, int count, bool required, const char* what, Range range = Range::Any) {
    const TiXmlAttribute* a = attribute(e, name);
    if (!a) {
      if (required)
        diag_.error(mark(e), fmt::format("<{}> needs a {} attribute ({} {}), found none", e.Value(), name, count_text(count), what));
      return;
    }
    const std::string_view text = a->Value();
    std::vector<double> values;
    std::string bad;  // why a token is not a number
    size_t i = 0;
    while (bad.empty()) {
      while (i < text.size() && is_space(text[i])) ++i;
      if (i == text.size()) break;
      size_t end = i;
      while (end < text.size() && !is_space(text[end])) ++end;
      const std::string_view token = text.substr(i, end - i);
      double v = 0;
      const char* first = token.data() + (token.starts_with('+') ? 1 : 0);  // from_chars takes no '+'
      auto [ptr, ec] = std::from_chars(first, token.data() + token.size(), v);
      if (ec == std::errc::result_out_of_range)  // 1e999 overflows; 1e-400 underflows
        bad = std::abs(std::strtod(std::string(token).c_str(), nullptr)) < 1
                  ? fmt::format("'{}' is closer to 0 than a double can hold (write 0)", token)
                  : fmt::format("'{}' is beyond the range of a double", token);
      else if (ec != std::errc() || ptr != token.data() + token.size()) bad = fmt::format("'{}' is not a number", token);
      else if (!std::isfinite(v)) bad = fmt::format("'{}' is not a finite number", token);
      else if (range == Range::NotNegative && v < 0) bad = fmt::format("{} is negative", token);
      else if (range == Range::Unit && (v < 0 || v > 1)) bad = fmt::format("{} is outside 0 to 1", token);
      values.push_back(v);
      i = end;
    }
    if (bad.empty() && static_cast<int>(values.size()) == count) return;
    diag_.error(mark(*a), fmt::format("<{} {}>: expected {} {}{}, found '{}'{}", e.Value(), name, count_text(count), what,
                                      range == Range::NotNegative ? " (not negative)" : range == Range::Unit ? " (each 0 to 1)" : "",
                                      text, bad.empty() ? fmt::format(" ({} of them)", values.size()) : ": " + bad));
  }

  void origin(const TiXmlElement& parent) {
    for (const TiXmlElement* o = parent.FirstChildElement("origin"); o; o = o->NextSiblingElement("origin")) {
      numbers(*o, "xyz", 3, false, "lengths in m");
      numbers(*o, "rpy", 3, false, "angles in rad");
    }
  }

  void color(const TiXmlElement& material) {
    if (const TiXmlElement* c = material.FirstChildElement("color")) numbers(*c, "rgba", 4, true, "colour channels", Range::Unit);
  }

  /// A <visual> or <collision>: its origin, its one shape, its material's colour.
  void shape_element(const TiXmlElement& e) {
    origin(e);
    const TiXmlElement* g = e.FirstChildElement("geometry");
    if (!g) {
      diag_.error(mark(e), fmt::format("<{}> needs a <geometry>, found none", e.Value()));
      return;
    }
    const TiXmlElement* shape = g->FirstChildElement();
    if (!shape) {
      diag_.error(mark(*g), "<geometry> needs one of <box>, <cylinder>, <sphere> or <mesh>, found nothing");
      return;
    }
    if (const TiXmlElement* second = shape->NextSiblingElement())
      diag_.error(mark(*second), fmt::format("<geometry> holds one shape, found a second: <{}>", second->Value()));
    const std::string_view kind = shape->Value();
    if (kind == "box") {
      numbers(*shape, "size", 3, true, "lengths in m", Range::NotNegative);
    } else if (kind == "cylinder") {
      numbers(*shape, "radius", 1, true, "length in m", Range::NotNegative);
      numbers(*shape, "length", 1, true, "length in m", Range::NotNegative);
    } else if (kind == "sphere") {
      numbers(*shape, "radius", 1, true, "length in m", Range::NotNegative);
    } else if (kind == "mesh") {
      const char* file = shape->Attribute("filename");
      if (!file || !*file) diag_.error(mark(*shape), "<mesh> needs a filename attribute (the mesh file), found none");
      numbers(*shape, "scale", 3, false, "scale factors");
    } else {
      diag_.error(mark(*shape), fmt::format("<geometry> needs one of <box>, <cylinder>, <sphere> or <mesh>, found <{}>", kind));
    }
    if (const TiXmlElement* m = e.FirstChildElement("material")) color(*m);
  }

  void link(const TiXmlElement& l) {
    for (const TiXmlElement* e = l.FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string_view kind = e->Value();
      if (kind == "visual" || kind == "collision") shape_element(*e);
    }
    if (const TiXmlElement* in = l.FirstChildElement("inertial")) {
      origin(*in);
      if (const TiXmlElement* m = in->FirstChildElement("mass")) numbers(*m, "value", 1, true, "mass in kg", Range::NotNegative);
      else diag_.error(mark(*in), "<inertial> needs a <mass value=...>, found none");
      if (const TiXmlElement* i = in->FirstChildElement("inertia"))
        for (const char* k : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}) numbers(*i, k, 1, true, "moment of inertia in kg m^2");
      else diag_.error(mark(*in), "<inertial> needs an <inertia ixx= ixy= ixz= iyy= iyz= izz=>, found none");
    }
  }

  void joint(const TiXmlElement& j) {
    origin(j);
    if (const TiXmlElement* a = j.FirstChildElement("axis")) {
      numbers(*a, "xyz", 3, false, "axis components");
      // urdfdom reads "0 0 0" and normalises it to NaN: a joint that moves along no direction.
      const char* type = j.Attribute("type");
      if (attribute(*a, "xyz") && zero_vector(attribute(*a, "xyz")->Value()) && type && std::string_view(type) != "fixed")
        diag_.error(mark(*attribute(*a, "xyz")), fmt::format("joint '{}': <axis xyz=\"{}\"> is the zero vector: a joint needs a "
                                                             "direction (write its unit axis, such as \"0 0 1\")",
                                                             j.Attribute("name") ? j.Attribute("name") : "?", attribute(*a, "xyz")->Value()));
    }
    if (const TiXmlElement* l = j.FirstChildElement("limit")) {
      numbers(*l, "lower", 1, false, "joint value");
      numbers(*l, "upper", 1, false, "joint value");
      numbers(*l, "velocity", 1, false, "speed", Range::NotNegative);
      numbers(*l, "effort", 1, false, "force or torque", Range::NotNegative);
      // A URDF's 0 is how many files say "not given" (urdfdom requires both attributes); sscs
      // then uses its defaults, and says so, for a drive without speed or force is no drive.
      const char* type = j.Attribute("type");
      const char* name = j.Attribute("name");
      if (type && std::string_view(type) != "fixed" && name) {
        const bool revolute = std::string_view(type) != "prismatic";
        for (const TiXmlAttribute* a = l->FirstAttribute(); a; a = a->Next()) {  // in the file's order
          const std::string_view key = a->Name();
          if (key == "velocity" && zero(*l, "velocity"))
            diag_.warning(mark(*a), fmt::format("joint '{}': <limit velocity=\"0\"> is taken as not given: it moves at the default {} "
                                                "(write its speed to time runs)", name, revolute ? "90 deg/s" : "0.5 m/s"));
          if (key == "effort" && zero(*l, "effort"))
            diag_.warning(mark(*a), fmt::format("joint '{}': <limit effort=\"0\"> is taken as not given: a run drives it with the "
                                                "default {}, 1e5 {}", name, revolute ? "torque" : "force", revolute ? "N m" : "N"));
        }
      }
    }
    if (const TiXmlElement* s = j.FirstChildElement("safety_controller")) {
      for (const char* k : {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}) numbers(*s, k, 1, false, "number");
      const bool lower = attribute(*s, "soft_lower_limit"), upper = attribute(*s, "soft_upper_limit");
      if (lower != upper)
        diag_.warning(mark(*s), fmt::format("joint '{}': <safety_controller> gives no {}: it is 0, as the URDF format "
                                            "defines it and MoveIt reads it (write it, or choose `joint_limits: hard`)",
                                            j.Attribute("name") ? j.Attribute("name") : "?",
                                            lower ? "soft_upper_limit" : "soft_lower_limit"));
    }
    if (const TiXmlElement* d = j.FirstChildElement("dynamics"))
      for (const char* k : {"damping", "friction"}) numbers(*d, k, 1, false, "number");
    if (const TiXmlElement* m = j.FirstChildElement("mimic"))
      for (const char* k : {"multiplier", "offset"}) numbers(*m, k, 1, false, "number");
    if (const TiXmlElement* c = j.FirstChildElement("calibration"))
      for (const char* k : {"rising", "falling"}) numbers(*c, k, 1, false, "joint value");
  }

 private:
  /// Whether `text` is three numbers, all 0.
  static bool zero_vector(std::string_view text) {
    int zeros = 0;
    for (size_t i = 0; i < text.size();) {
      while (i < text.size() && is_space(text[i])) ++i;
      if (i == text.size()) break;
      size_t end = i;
      while (end < text.size() && !is_space(text[end])) ++end;
      double v = 1;
      const char* first = text.data() + i + (text[i] == '+' ? 1 : 0);
      auto [ptr, ec] = std::from_chars(first, text.data() + end, v);
      if (ec != std::errc() || ptr != text.data() + end || v != 0) return false;
      ++zeros;
      i = end;
    }
    return zeros == 3;
  }
  /// Whether attribute `name` of `e` is a number equal to 0.
  static bool zero(const TiXmlElement& e, const char* name) {
    const TiXmlAttribute* a = attribute(e, name);
    if (!a) return false;
    double v = 1;
    const std::string_view text = a->Value();
    size_t b = text.find_first_not_of(" \t\r\n"), t = text.find_last_not_of(" \t\r\n");
    if (b == std::string_view::npos) return false;
    auto [ptr, ec] = std::from_chars(text.data() + b, text.data() + t + 1, v);
    return ec == std::errc() && ptr == text.data() + t + 1 && v == 0;
  }
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
  static std::string count_text(int n) { return n == 1 ? "a finite" : fmt::format("{} finite", n); }
  static const TiXmlAttribute* attribute(const TiXmlElement& e, const char* name) {
    for (const TiXmlAttribute* a = e.FirstAttribute(); a; a = a->Next())
      if (std::string_view(a->Name()) == name) return a;
    return nullptr;
  }

  uint32_t file_;
  Diagnostics& diag_;
};

}  // namespace

namespace {

/// The line and column (1-based, in bytes) of byte `offset` of `text`.
SourceMark offset_mark(uint32_t file, const std::string& text, size_t offset) {
  uint32_t line = 1, column = 1;
  for (size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {file, line, column};
}

bool is_xml_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

/// The first element under `e` (itself included) in the xacro namespace, or null.
const TiXmlElement* first_xacro(const TiXmlElement& e) {
  if (std::string_view(e.Value()).starts_with("xacro:")) return &e;
  for (const TiXmlElement* c = e.FirstChildElement(); c; c = c->NextSiblingElement())
    if (const TiXmlElement* x = first_xacro(*c)) return x;
  return nullptr;
}

}  // namespace

SourceMark xml_mark(uint32_t file, const TiXmlBase& at) {
  return {file, static_cast<uint32_t>(std::max(1, at.Row())), static_cast<uint32_t>(std::max(1, at.Column()))};
}

const TiXmlElement* read_robot_xml(const char* what, const std::string& type_file, const Scalar& at, Sources& sources,
                                   Diagnostics& diag, TiXmlDocument& doc, uint32_t& file) {
  file = 0;
  if (missing_reference(what, type_file, at.text, at.mark, diag)) return nullptr;
  file = read_source(resolve_mesh_path(type_file, at.text), sources, diag, at.mark);
  if (file == 0) return nullptr;
  const std::string& text = sources.text(file);
  // The parser stops at a NUL byte, so what follows would be lost (and the error put at 1:1).
  if (size_t nul = text.find('\0'); nul != std::string::npos) {
    diag.error(offset_mark(file, text, nul), fmt::format("cannot read {} '{}': a NUL byte; an XML file is text", what, at.text));
    return nullptr;
  }
  doc.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc.Error()) {
    SourceMark where{file, static_cast<uint32_t>(std::max(1, doc.ErrorRow())), static_cast<uint32_t>(std::max(1, doc.ErrorCol()))};
    diag.error(where, fmt::format("cannot read {} '{}': {}", what, at.text, doc.ErrorDesc()));
    return nullptr;
  }
  const TiXmlElement* robot = nullptr;
  for (const TiXmlNode* n = doc.FirstChild(); n; n = n->NextSibling()) {
    if (const TiXmlUnknown* u = n->ToUnknown()) {
      // TinyXML reads no DTD: entities declared there would stay unexpanded, or end the parse.
      if (std::string_view(u->Value()).starts_with("!DOCTYPE")) {
        diag.error(xml_mark(file, *u), fmt::format("cannot read {} '{}': it has a <!DOCTYPE>, which sscs does not read "
                                                   "(robot files have none; expand its entities and remove it)", what, at.text));
        return nullptr;
      }
    } else if (const TiXmlElement* e = n->ToElement()) {
      if (robot) {  // the parser stops at the end of the first element: anything after it is lost
        diag.error(xml_mark(file, *e), fmt::format("{} '{}': <{}> after </{}>: a file holds one robot", what, at.text,
                                                   e->Value(), robot->Value()));
        return nullptr;
      }
      robot = e;
    } else if (const TiXmlText* t = n->ToText()) {
      diag.error(xml_mark(file, *t), fmt::format("{} '{}': text outside the <robot> element", what, at.text));
      return nullptr;
    }
  }
  // TinyXML drops text after the root element without a word: only space and comments may follow.
  if (robot) {
    const std::string closing = fmt::format("</{}", robot->Value());
    if (size_t end = text.rfind(closing); end != std::string::npos && (end = text.find('>', end)) != std::string::npos) {
      size_t i = end + 1;
      while (i < text.size()) {
        if (is_xml_space(text[i])) {
          ++i;
        } else if (text.compare(i, 4, "<!--") == 0 && text.find("-->", i + 4) != std::string::npos) {
          i = text.find("-->", i + 4) + 3;
        } else {
          diag.error(offset_mark(file, text, i), fmt::format("{} '{}': '{}' after </{}>: a file holds one robot and nothing after it",
                                                           what, at.text, printable(text.substr(i, std::min(text.find_first_of("\r\n", i), i + 20) - i)),
                                                           robot->Value()));
          return nullptr;
        }
      }
    }
  }
  if (!robot || std::string_view(robot->Value()) != "robot") {
    if (robot) diag.error(xml_mark(file, *robot), fmt::format("{} '{}' has <{}> at its top, not <robot>", what, at.text, robot->Value()));
    else diag.error(at.mark, fmt::format("{} '{}' has no <robot> element at its top", what, at.text));
    return nullptr;
  }
  // A xacro file is a program that writes a URDF: read as one, its macros' links would vanish.
  if (const TiXmlElement* x = first_xacro(*robot)) {
    diag.error(xml_mark(file, *x), fmt::format("{} '{}' is a xacro file (<{}>): expand it first, `xacro {} > robot.urdf`, "
                                               "and name the expanded file", what, at.text, x->Value(), at.text));
    return nullptr;
  }
  return robot;
}

void check_urdf_tree(const TiXmlElement& robot, uint32_t file, Diagnostics& diag) {
  // child link -> the joint that makes it a child, and that joint's parent link
  std::map<std::string, std::pair<const TiXmlElement*, std::string>> parent_of;
  auto link_of = [](const TiXmlElement& joint, const char* role) -> std::string {
    const TiXmlElement* e = joint.FirstChildElement(role);
    const char* name = e ? e->Attribute("link") : nullptr;
    return name ? name : "";
  };
  auto name_of = [](const TiXmlElement& e) -> std::string { return e.Attribute("name") ? e.Attribute("name") : "?"; };
  // What urdfdom refuses with a message and no place (the type file's `urdf:` line was all a
  // user got), found here at its element: names given twice, a joint's missing or unknown
  // links, a moving joint without <limit>, a <mimic> without its joint, two roots.
  // The elements of one kind by name; false (reported) when a name is given twice.
  auto by_name = [&](const char* kind, std::map<std::string, const TiXmlElement*>& out) {
    for (const TiXmlElement* e = robot.FirstChildElement(kind); e; e = e->NextSiblingElement(kind))
      if (auto [it, fresh] = out.try_emplace(name_of(*e), e); !fresh) {
        diag.error(xml_mark(file, *e), fmt::format("{} '{}' is defined twice (first at line {}): {} names are unique", kind, it->first,
                                                   it->second->Row(), kind));
        return false;
      }
    return true;
  };
  std::map<std::string, const TiXmlElement*> links, joints;
  if (!by_name("link", links) || !by_name("joint", joints)) return;
  for (const TiXmlElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const std::string name = name_of(*j);
    for (const char* role : {"parent", "child"}) {
      const TiXmlElement* e = j->FirstChildElement(role);
      const std::string link = link_of(*j, role);
      if (link.empty()) {
        diag.error(xml_mark(file, e ? *e : *j), fmt::format("joint '{}' has no <{} link=\"...\">: a joint joins a parent link and a child link",
                                                            name, role));
        return;
      }
      if (!links.count(link)) {
        diag.error(xml_mark(file, *e), fmt::format("joint '{}': its {} link '{}' is not a link of this robot", name, role, link));
        return;
      }
    }
    const char* type = j->Attribute("type");
    const bool ranged = type && (std::string_view(type) == "revolute" || std::string_view(type) == "prismatic");
    const TiXmlElement* limit = j->FirstChildElement("limit");
    if (ranged && !limit) {
      diag.error(xml_mark(file, *j), fmt::format("joint '{}' is {} and has no <limit> (a URDF gives revolute and prismatic joints their "
                                                 "limits; a joint that turns without end is continuous)", name, type));
      return;
    }
    if (limit && type && std::string_view(type) != "fixed") {
      for (const char* needed : {"effort", "velocity"})
        if (!limit->Attribute(needed)) {
          diag.error(xml_mark(file, *limit), fmt::format("joint '{}': <limit> has no {}= (a URDF's limits carry the joint's effort and "
                                                         "velocity; urdfdom refuses the file without them)", name, needed));
          return;
        }
      if (ranged && (!limit->Attribute("lower") || !limit->Attribute("upper")))
        diag.warning(xml_mark(file, *limit), fmt::format("joint '{}': <limit> gives no {}: URDF reads it as 0, so the joint's range is "
                                                         "[{}, {}]{}", name, !limit->Attribute("lower") && !limit->Attribute("upper") ? "lower or upper" : !limit->Attribute("lower") ? "lower" : "upper",
                                                         limit->Attribute("lower") ? limit->Attribute("lower") : "0",
                                                         limit->Attribute("upper") ? limit->Attribute("upper") : "0",
                                                         !limit->Attribute("lower") && !limit->Attribute("upper") ? " and it cannot move" : ""));
    }
    if (const TiXmlElement* m = j->FirstChildElement("mimic"); m && !m->Attribute("joint")) {
      diag.error(xml_mark(file, *m), fmt::format("joint '{}': <mimic> names no joint (joint=\"...\")", name));
      return;
    }
  }
  for (const TiXmlElement* j = robot.FirstChildElement("joint"); j; j = j->NextSiblingElement("joint")) {
    const std::string parent = link_of(*j, "parent"), child = link_of(*j, "child");
    auto [it, fresh] = parent_of.try_emplace(child, j, parent);
    if (!fresh) {
      diag.error(xml_mark(file, *j), fmt::format("joint '{}': link '{}' is already the child of joint '{}': a link has one parent "
                                                 "(a device is a tree)", name_of(*j), child, name_of(*it->second.first)));
      return;
    }
  }
  // Follow each link's parents up: coming back to a link is a loop of joints.
  std::set<std::string> done;
  for (const auto& [start, unused] : parent_of) {
    std::vector<std::string> path;
    std::string link = start;
    while (!done.count(link)) {
      if (std::find(path.begin(), path.end(), link) != path.end()) {
        std::vector<std::string> loop(std::find(path.begin(), path.end(), link), path.end());
        std::reverse(loop.begin(), loop.end());
        loop.push_back(loop.front());
        // Reported at the loop's joint that comes last in the file: the one that closes it.
        const TiXmlElement* closing = parent_of.at(link).first;
        for (size_t k = 0; k + 1 < loop.size(); ++k)
          if (const TiXmlElement* j = parent_of.at(loop[k]).first; j->Row() > closing->Row()) closing = j;
        diag.error(xml_mark(file, *closing), fmt::format("joint '{}' closes a loop of links ({}): a device is a tree (model the loop's "
                                                         "last joint as a constraint in a plugin, or drop it)",
                                                         name_of(*closing), fmt::join(loop, " -> ")));
        return;
      }
      path.push_back(link);
      auto up = parent_of.find(link);
      if (up == parent_of.end()) break;
      link = up->second.second;
    }
    done.insert(path.begin(), path.end());
  }
  // One root: the links no joint makes a child.
  const TiXmlElement* root = nullptr;
  for (const TiXmlElement* l = robot.FirstChildElement("link"); l; l = l->NextSiblingElement("link")) {
    if (parent_of.count(name_of(*l))) continue;
    if (root) {
      diag.error(xml_mark(file, *l), fmt::format("link '{}' is a second root (no joint makes it a child; '{}' at line {} is the first): "
                                                 "a device is one tree of links", name_of(*l), name_of(*root), root->Row()));
      return;
    }
    root = l;
  }
}

void check_urdf_numbers(const TiXmlElement& robot, uint32_t file, Diagnostics& diag) {
  UrdfChecker check(file, diag);
  std::set<std::string_view> joints;
  for (const TiXmlElement* e = robot.FirstChildElement("joint"); e; e = e->NextSiblingElement("joint"))
    if (const char* name = e->Attribute("name")) joints.insert(name);
  for (const TiXmlElement* e = robot.FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string_view kind = e->Value();
    if (kind == "link") check.link(*e);
    else if (kind == "joint") check.joint(*e);
    else if (kind == "material") check.color(*e);
    if (kind != "joint") continue;
    // sscs moves a mimic joint on its own, but a mimic of no joint is a broken file elsewhere.
    if (const TiXmlElement* m = e->FirstChildElement("mimic")) {
      const char* of = m->Attribute("joint");
      if (of && !joints.count(of))  // one without joint= is an error of check_urdf_tree
        diag.warning(xml_mark(file, *m), fmt::format("joint '{}': <mimic joint=\"{}\"> names no joint of this robot (sscs moves "
                                                     "mimic joints on their own, so nothing changes here)",
                                                     e->Attribute("name") ? e->Attribute("name") : "?", of ? of : ""));
    }
  }
}

}  // namespace sscs
