// Checks a URDF's numbers element by element, as the URDF format defines them
// (http://wiki.ros.org/urdf/XML), before urdfdom reads the file.
#include "load/urdf_xml.h"

#include <charconv>
#include <cmath>
#include <string_view>
#include <vector>

#include <fmt/format.h>
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
      if (ec == std::errc::result_out_of_range) bad = fmt::format("'{}' is beyond the range of a double", token);
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
    if (const TiXmlElement* a = j.FirstChildElement("axis")) numbers(*a, "xyz", 3, false, "axis components");
    if (const TiXmlElement* l = j.FirstChildElement("limit")) {
      numbers(*l, "lower", 1, false, "joint value");
      numbers(*l, "upper", 1, false, "joint value");
      numbers(*l, "velocity", 1, false, "speed", Range::NotNegative);
      numbers(*l, "effort", 1, false, "force or torque", Range::NotNegative);
    }
    if (const TiXmlElement* s = j.FirstChildElement("safety_controller"))
      for (const char* k : {"soft_lower_limit", "soft_upper_limit", "k_position", "k_velocity"}) numbers(*s, k, 1, false, "number");
    if (const TiXmlElement* d = j.FirstChildElement("dynamics"))
      for (const char* k : {"damping", "friction"}) numbers(*d, k, 1, false, "number");
    if (const TiXmlElement* m = j.FirstChildElement("mimic"))
      for (const char* k : {"multiplier", "offset"}) numbers(*m, k, 1, false, "number");
    if (const TiXmlElement* c = j.FirstChildElement("calibration"))
      for (const char* k : {"rising", "falling"}) numbers(*c, k, 1, false, "joint value");
  }

 private:
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

SourceMark xml_mark(uint32_t file, const TiXmlBase& at) {
  return {file, static_cast<uint32_t>(std::max(1, at.Row())), static_cast<uint32_t>(std::max(1, at.Column()))};
}

const TiXmlElement* read_robot_xml(const char* what, const std::string& type_file, const Scalar& at, Sources& sources,
                                   Diagnostics& diag, TiXmlDocument& doc, uint32_t& file) {
  file = 0;
  if (missing_reference(what, type_file, at.text, at.mark, diag)) return nullptr;
  file = read_source(resolve_mesh_path(type_file, at.text), sources, diag, at.mark);
  if (file == 0) return nullptr;
  doc.Parse(sources.text(file).c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc.Error()) {
    SourceMark where{file, static_cast<uint32_t>(std::max(1, doc.ErrorRow())), static_cast<uint32_t>(std::max(1, doc.ErrorCol()))};
    diag.error(where, fmt::format("cannot read {} '{}': {}", what, at.text, doc.ErrorDesc()));
    return nullptr;
  }
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string_view(robot->Value()) != "robot") {
    diag.error(at.mark, fmt::format("{} '{}' has no <robot> element at its top", what, at.text));
    return nullptr;
  }
  return robot;
}

void check_urdf_numbers(const TiXmlElement& robot, uint32_t file, Diagnostics& diag) {
  UrdfChecker check(file, diag);
  for (const TiXmlElement* e = robot.FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string_view kind = e->Value();
    if (kind == "link") check.link(*e);
    else if (kind == "joint") check.joint(*e);
    else if (kind == "material") check.color(*e);
  }
}

}  // namespace sscs
