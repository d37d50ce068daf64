#include "load/spec.h"

namespace sscs {

const char* constraint_kind_name(const ConstraintKind& kind) {
  return kConstraintKindNames[kind.index()];
}

std::vector<const MeshSpec*> named_meshes(const TypeSpec& spec) {
  std::vector<const MeshSpec*> out;
  auto add = [&](const std::vector<GeometrySpec>& geometry) {
    for (const GeometrySpec& g : geometry)
      if (const MeshSpec* m = std::get_if<MeshSpec>(&g.shape)) out.push_back(m);
  };
  add(spec.geometry);
  if (spec.device)
    for (const PartSpec& part : spec.device->parts) {
      add(part.geometry);
      add(part.visual);
    }
  return out;
}

}  // namespace sscs
