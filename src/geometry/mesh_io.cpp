#include "geometry/mesh_io.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <functional>

#include <fmt/format.h>

namespace sscs {

namespace {

/// assimp reads coordinates in single precision: 1.2 in a file arrives as 1.2000000477, which
/// would make a pallet 48 nm longer than written and a clearance of exactly its minimum fail.
/// A float holds about 7 significant digits, so rounding to 7 gives back the decimal the file
/// wrote (and changes nothing a float could tell apart).
double as_written(float x) {
  if (!std::isfinite(x) || x == 0) return x;
  char text[32];
  auto [end, ec] = std::to_chars(text, text + sizeof text, static_cast<double>(x), std::chars_format::scientific, 6);
  double value = x;
  if (ec == std::errc()) std::from_chars(text, end, value);
  return value;
}

}  // namespace

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
          mesh->vertices.emplace_back(as_written(am->mVertices[v].x), as_written(am->mVertices[v].y), as_written(am->mVertices[v].z));
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
          const aiFace& face = am->mFaces[f];
          if (face.mNumIndices == 3)
            mesh->triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
        }
      }
      mesh->closed = is_closed(mesh->vertices, mesh->triangles);
      if (mesh->triangles.empty()) diag.error(where, fmt::format("mesh '{}' has no triangles", path));
      else result = std::move(mesh);
    }
  }
  meshes_[path] = result;
  return result;
}

bool is_closed(const std::vector<Eigen::Vector3d>& vertices, const std::vector<Eigen::Vector3i>& triangles) {
  if (triangles.empty()) return false;
  // Weld by exact position: formats repeat a corner per face (STL) or per normal (OBJ, glTF).
  std::map<std::array<double, 3>, int> ids;
  std::vector<int> weld(vertices.size());
  for (size_t v = 0; v < vertices.size(); ++v)
    weld[v] = ids.try_emplace({vertices[v].x(), vertices[v].y(), vertices[v].z()}, static_cast<int>(ids.size())).first->second;
  // Every edge is run as often in one direction as in the other: the boundary of a solid,
  // consistently oriented (pieces that touch along an edge, a pallet's boards and blocks, count).
  std::map<std::pair<int, int>, int> directed;
  for (const Eigen::Vector3i& t : triangles)
    for (int k = 0; k < 3; ++k) {
      int a = weld[t[k]], b = weld[t[(k + 1) % 3]];
      if (a != b) ++directed[{a, b}];  // a degenerate triangle adds no edge
    }
  for (const auto& [edge, n] : directed) {
    auto back = directed.find({edge.second, edge.first});
    if (back == directed.end() || back->second != n) return false;
  }
  return true;
}

}  // namespace sscs
