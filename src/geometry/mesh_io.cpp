#include "geometry/mesh_io.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <filesystem>
#include <functional>

#include <fmt/format.h>

namespace sscs {

std::shared_ptr<const TriangleMesh> MeshCache::load(const std::string& path, SourceMark where, Diagnostics& diag) {
  auto it = meshes_.find(path);
  if (it != meshes_.end()) return it->second;
  std::shared_ptr<const TriangleMesh> result;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    diag.error(where, fmt::format("mesh file '{}' does not exist", path));
  } else {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                       aiProcess_PreTransformVertices);
    if (!scene || !scene->mRootNode) {
      diag.error(where, fmt::format("cannot read mesh '{}': {}", path, importer.GetErrorString()));
    } else {
      auto mesh = std::make_shared<TriangleMesh>();
      mesh->path = path;
      for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* am = scene->mMeshes[m];
        auto base = static_cast<int>(mesh->vertices.size());
        for (unsigned v = 0; v < am->mNumVertices; ++v)
          mesh->vertices.emplace_back(am->mVertices[v].x, am->mVertices[v].y, am->mVertices[v].z);
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
          const aiFace& face = am->mFaces[f];
          if (face.mNumIndices == 3)
            mesh->triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
        }
      }
      if (mesh->triangles.empty()) diag.error(where, fmt::format("mesh '{}' has no triangles", path));
      else result = std::move(mesh);
    }
  }
  meshes_[path] = result;
  return result;
}

}  // namespace sscs
