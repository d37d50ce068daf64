#pragma once
/// Reading triangle meshes through assimp (STL, OBJ, PLY, glTF/GLB and the rest it reads).
#include <map>
#include <memory>
#include <string>

#include "core/diagnostics.h"
#include "geometry/geometry.h"

namespace sscs {

/// Loads each mesh file once. A file that is missing, unreadable or has no triangles is an input
/// error reported at `where` (the line that names the file).
class MeshCache {
 public:
  std::shared_ptr<const TriangleMesh> load(const std::string& path, SourceMark where, Diagnostics& diag);

 private:
  std::map<std::string, std::shared_ptr<const TriangleMesh>> meshes_;
};

}  // namespace sscs
