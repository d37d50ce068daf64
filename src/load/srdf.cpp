// A MoveIt SRDF beside a vendor's URDF: the link pairs it disables collision checking for
// (<disable_collisions link1= link2= reason=/>) become the device's allowed collisions. The rest
// of the file (groups, end effectors, virtual joints, passive joints) is read past.
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
  keep();
}

}  // namespace sscs
