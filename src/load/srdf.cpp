// A MoveIt SRDF beside a vendor's URDF: the link pairs it disables collision checking for
// (<disable_collisions link1= link2= reason=/>) become the device's allowed collisions. The rest
// of the file is read past (virtual and passive joints, group states), but for the tool of a type
// that names none: the SRDF's one end effector's parent link, else its one chain's tip link.
#include <tinyxml.h>

#include <fmt/format.h>

#include "core/files.h"
#include "load/load.h"

namespace sscs {

void load_srdf(DeviceSpec& device, const std::string& type_file, Sources& sources) {
  const Scalar& at = device.srdf;
  const std::string path = resolve_mesh_path(type_file, at.text);
  // Read like every input file (project root, size limit, not a FIFO), so errors point into it.
  Diagnostics diag;
  auto keep = [&] {
    for (const Diagnostic& d : diag.errors()) device.import_problems.push_back(d);
  };
  const uint32_t file = read_source(path, sources, diag, at.mark);
  if (file == 0) return keep();
  TiXmlDocument doc;
  doc.Parse(sources.text(file).c_str(), nullptr, TIXML_ENCODING_UTF8);
  if (doc.Error()) {
    SourceMark where{file, static_cast<uint32_t>(std::max(1, doc.ErrorRow())), static_cast<uint32_t>(std::max(1, doc.ErrorCol()))};
    diag.error(where, fmt::format("cannot read SRDF file '{}': {}", at.text, doc.ErrorDesc()));
    return keep();
  }
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Value()) != "robot") {
    diag.error(at.mark, fmt::format("SRDF file '{}' has no <robot> element at its top", at.text));
    return keep();
  }
  for (const TiXmlElement* e = robot->FirstChildElement("disable_collisions"); e; e = e->NextSiblingElement("disable_collisions")) {
    SourceMark where{file, static_cast<uint32_t>(std::max(1, e->Row())), static_cast<uint32_t>(std::max(1, e->Column()))};
    const char* a = e->Attribute("link1");
    const char* b = e->Attribute("link2");
    if (!a || !b) {
      diag.error(where, fmt::format("<disable_collisions> needs both link1 and link2, found {}", a ? "only link1" : b ? "only link2" : "neither"));
      continue;
    }
    device.allowed_collisions.push_back({a, b, where});
  }
  // A type without `tool:` takes the link the SRDF names as its tool: its one end effector's
  // parent link, else the tip of its one chain group.
  if (device.tool_part.empty()) {
    std::vector<std::pair<std::string, SourceMark>> effectors, tips;
    auto mark_of = [&](const TiXmlElement* e) {
      return SourceMark{file, static_cast<uint32_t>(std::max(1, e->Row())), static_cast<uint32_t>(std::max(1, e->Column()))};
    };
    for (const TiXmlElement* e = robot->FirstChildElement("end_effector"); e; e = e->NextSiblingElement("end_effector"))
      if (const char* link = e->Attribute("parent_link")) effectors.emplace_back(link, mark_of(e));
    for (const TiXmlElement* g = robot->FirstChildElement("group"); g; g = g->NextSiblingElement("group"))
      for (const TiXmlElement* c = g->FirstChildElement("chain"); c; c = c->NextSiblingElement("chain"))
        if (const char* tip = c->Attribute("tip_link")) tips.emplace_back(tip, mark_of(c));
    const auto& from = effectors.size() == 1 ? effectors : tips;
    if (from.size() == 1) {
      device.tool_part = from[0].first;
      device.tool_mark = from[0].second;
    }
  }
  keep();
}

}  // namespace sscs
