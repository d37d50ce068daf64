// A MoveIt SRDF beside a vendor's URDF: the link pairs it disables collision checking for
// (<disable_collisions link1= link2= reason=/>, <disable_default_collisions link=/> for a link
// with every other, less the <enable_collisions> pairs) become the device's allowed collisions.
// The rest of the file is read past (virtual and passive joints, group states), but for the tool
// of a type that names none: the SRDF's one end effector's parent link, else its one chain's tip
// link; a file that names several of each is warned about, for it names no one tool.
#include <algorithm>
#include <optional>

#include <tinyxml.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/files.h"
#include "load/load.h"
#include "load/urdf_xml.h"

namespace sscs {

void load_srdf(DeviceSpec& device, const std::string& type_file, Sources& sources) {
  const Scalar& at = device.srdf;
  Diagnostics diag;
  auto keep = [&] {
    for (const Diagnostic& d : diag.warnings()) device.import_problems.push_back({d.mark, d.message, true});
    for (const Diagnostic& d : diag.errors()) device.import_problems.push_back(d);
  };
  TiXmlDocument doc;
  uint32_t file = 0;
  const TiXmlElement* robot = read_robot_xml("SRDF file", type_file, at, sources, diag, doc, file);
  if (!robot) return keep();
  auto mark_of = [&](const TiXmlElement* e) { return xml_mark(file, *e); };
  const char* robot_name = robot->Attribute("name");
  if (!robot_name || !*robot_name)  // MoveIt refuses an SRDF without the robot's name
    diag.warning(mark_of(robot), fmt::format("this SRDF's <robot> has no name (MoveIt requires one: the URDF's, '{}')",
                                             device.urdf_robot));
  else if (!device.urdf_robot.empty() && device.urdf_robot != robot_name)
    diag.warning(mark_of(robot), fmt::format("this SRDF is for robot '{}', but the URDF is robot '{}' (is the SRDF another robot's?)",
                                             robot_name, device.urdf_robot));
  // Pairs: <disable_collisions link1 link2/>, and <disable_default_collisions link/> (MoveIt 1.1 and
  // later: that link with every other); <enable_collisions link1 link2/> takes a pair back.
  auto pair_of = [&](const TiXmlElement* e, const char* what) -> std::optional<std::pair<std::string, std::string>> {
    const char* a = e->Attribute("link1");
    const char* b = e->Attribute("link2");
    if (a && b) return std::make_pair(std::string(a), std::string(b));
    diag.error(mark_of(e), fmt::format("<{}> needs both link1 and link2, found {}", what, a ? "only link1" : b ? "only link2" : "neither"));
    return std::nullopt;
  };
  // As MoveIt applies them: the default-disabled links' pairs, less the enabled pairs, then the
  // disabled pairs (a pair both enabled and disabled is disabled: allowed).
  std::vector<DeviceSpec::AllowedCollision> defaults;
  for (const TiXmlElement* e = robot->FirstChildElement("disable_default_collisions"); e;
       e = e->NextSiblingElement("disable_default_collisions")) {
    const char* link = e->Attribute("link");
    if (!link) {
      diag.error(mark_of(e), "<disable_default_collisions> needs a link attribute, found none");
      continue;
    }
    const bool known = std::any_of(device.parts.begin(), device.parts.end(), [&](const PartSpec& p) { return p.name == link; });
    if (!known) {
      diag.error(mark_of(e), fmt::format("this <disable_default_collisions> names '{}', which is no link of the robot (is the SRDF "
                                         "another robot's?)", link));
      continue;
    }
    for (const PartSpec& p : device.parts)
      if (p.name != link) defaults.push_back({link, p.name, mark_of(e)});
  }
  for (const TiXmlElement* e = robot->FirstChildElement("enable_collisions"); e; e = e->NextSiblingElement("enable_collisions"))
    if (auto p = pair_of(e, "enable_collisions"))
      std::erase_if(defaults, [&](const DeviceSpec::AllowedCollision& c) {
        return (c.a == p->first && c.b == p->second) || (c.a == p->second && c.b == p->first);
      });
  device.allowed_collisions.insert(device.allowed_collisions.end(), defaults.begin(), defaults.end());
  for (const TiXmlElement* e = robot->FirstChildElement("disable_collisions"); e; e = e->NextSiblingElement("disable_collisions"))
    if (auto p = pair_of(e, "disable_collisions")) device.allowed_collisions.push_back({p->first, p->second, mark_of(e)});
  // A type without `tool:` takes the link the SRDF names as its tool: its one end effector's
  // parent link, else the tip of its one chain group.
  if (device.tool_part.empty()) {
    std::vector<std::pair<std::string, SourceMark>> effectors, tips;
    for (const TiXmlElement* e = robot->FirstChildElement("end_effector"); e; e = e->NextSiblingElement("end_effector"))
      if (const char* link = e->Attribute("parent_link")) effectors.emplace_back(link, mark_of(e));
    for (const TiXmlElement* g = robot->FirstChildElement("group"); g; g = g->NextSiblingElement("group"))
      for (const TiXmlElement* c = g->FirstChildElement("chain"); c; c = c->NextSiblingElement("chain"))
        if (const char* tip = c->Attribute("tip_link")) tips.emplace_back(tip, mark_of(c));
    const auto& from = effectors.size() == 1 ? effectors : tips;
    if (from.size() == 1) {
      device.tool_part = from[0].first;
      device.tool_mark = from[0].second;
    } else if (effectors.size() > 1 || tips.size() > 1) {
      auto names = [](const std::vector<std::pair<std::string, SourceMark>>& v) {
        std::vector<std::string> out;
        for (const auto& [name, mark] : v) out.push_back(name);
        return fmt::format("{}", fmt::join(out, ", "));
      };
      diag.warning(mark_of(robot), fmt::format("this SRDF names {} end effector parent links ({}) and {} chain tips ({}): no one tool; "
                                               "the tool is the end of the longest chain (write tool: in the type to choose)",
                                               effectors.size(), names(effectors), tips.size(), names(tips)));
    }
  }
  keep();
}

}  // namespace sscs
