#include "cli/type_listing.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "geometry/geometry.h"
#include "model/device.h"
#include "kinematics/envelope.h"
#include "load/load.h"

namespace sscs {

TypeInstance instance_at_defaults(const std::shared_ptr<const std::vector<ObjectType>>& library, const ObjectType& type,
                                  const CompileOptions& base) {
  TypeInstance out;
  Sources sources;
  Diagnostics diag;
  CompileOptions options = base;
  options.library = library;
  uint32_t file = sources.add("<types>", fmt::format("sscs: 1\nvault: types\nobjects:\n  - {{type: {}, name: Instance}}\n", type.name));
  auto spec = load_vault(file, sources, diag);
  std::optional<Workcell> wc;
  if (spec && !diag.has_errors()) wc = compile(*spec, options, sources, diag);
  GeometryModel geometry;
  if (wc) geometry = build_geometry(*wc, diag);
  if (!wc || diag.has_errors() || geometry.objects.empty()) {
    out.unbuilt = diag.errors().empty() ? "it cannot be instanced" : diag.errors()[0].message;
    return out;
  }
  const ObjectGeometry& g = geometry.objects[0];
  out.bounds = g.bbox_world;  // the instance stands at the origin: world is the type's frame
  // `top` (what a reach or move_to targets by default), then the frames the type files name.
  out.frames.emplace_back("top", g.frame_pose("top"));
  std::vector<std::string> named;
  for (int k = wc->objects[0].type; k >= 0; k = wc->types[k].base)
    for (const FrameSpec& f : wc->types[k].spec->frames) named.push_back(f.name);
  std::sort(named.begin(), named.end());
  named.erase(std::unique(named.begin(), named.end()), named.end());
  for (const std::string& name : named)
    if (const Eigen::Isometry3d* X = g.frame(name); X && name != "top") out.frames.emplace_back(name, *X);
  const std::filesystem::path folder = std::filesystem::absolute(type.spec->path).parent_path();
  auto add_mesh = [&](const Shape& s) {
    if (s.kind != Shape::Kind::Mesh || !s.mesh) return;
    std::string rel = std::filesystem::absolute(s.mesh->path).lexically_normal().lexically_relative(folder.lexically_normal()).string();
    if (rel.empty()) rel = s.mesh->path;
    for (const TypeInstance::Mesh& m : out.meshes)
      if (m.file == rel) return;
    out.meshes.push_back({rel, s.mesh->closed});
  };
  for (const Shape& s : g.shapes) add_mesh(s);
  if (g.device) {
    for (const Part& p : g.device->parts)
      for (const Shape& s : p.shapes) add_mesh(s);
    if (const Eigen::Isometry3d* X = g.frame("tool")) out.frames.emplace_back("tool", *X);
    out.reach = reach_envelope(*g.device, g.device->joint_values(&wc->values[wc->objects[0].first_slot + kFirstAttributeSlot]));
  }
  return out;
}

}  // namespace sscs
