#include "geometry/mesh_io.h"

#include "core/files.h"
#include "core/limits.h"
#include "core/units.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
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

/// Why a mesh file must not reach assimp: too large (it would take many times its size in
/// memory), or a binary glTF whose header does not match the file (assimp reads a corrupt 22-byte
/// .glb into gigabytes). "" when it may be read.
std::string unfit_mesh_file(const std::string& path) {
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(path, ec);
  const uintmax_t limit = limit_bytes("SSCS_MAX_MESH_MB", kMaxMeshFileMb);
  if (!ec && size > limit)
    return fmt::format("it is {:.0f} MB, above the {:.0f} MB limit of a mesh file (raise it with SSCS_MAX_MESH_MB)",
                       size / 1e6, limit / 1e6);
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".glb") {
    // Header: magic "glTF", version 2, total length; then a JSON chunk (length, "JSON").
    std::ifstream in(path, std::ios::binary);
    unsigned char h[20] = {};
    in.read(reinterpret_cast<char*>(h), sizeof h);
    auto u32 = [&](int at) { return uint32_t(h[at]) | uint32_t(h[at + 1]) << 8 | uint32_t(h[at + 2]) << 16 | uint32_t(h[at + 3]) << 24; };
    if (in.gcount() < 20 || std::memcmp(h, "glTF", 4) != 0) return "not a binary glTF file (no 'glTF' header)";
    if (u32(4) != 2) return fmt::format("binary glTF version {}, expected 2", u32(4));
    if (u32(8) != size) return fmt::format("its header says {} bytes, the file has {}: truncated or corrupt", u32(8), size);
    if (uint64_t(u32(12)) + 20 > size || std::memcmp(h + 16, "JSON", 4) != 0) return "its first chunk is no JSON chunk within the file";
  }
  return "";
}

}  // namespace

std::shared_ptr<const TriangleMesh> MeshCache::load(const std::string& path, SourceMark where, Diagnostics& diag) {
  auto it = meshes_.find(path);
  if (it != meshes_.end()) return it->second;
  std::shared_ptr<const TriangleMesh> result;
  if (std::string why = not_a_file(path); !why.empty()) {
    diag.error(where, fmt::format("mesh file '{}' {}", path, why));
  } else if (std::string why = unfit_mesh_file(path); !why.empty()) {
    diag.error(where, fmt::format("cannot read mesh '{}': {}", path, why));
  } else {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                       aiProcess_PreTransformVertices);
    if (!scene || !scene->mRootNode) {
      diag.error(where, fmt::format("cannot read mesh '{}': {}", path, importer.GetErrorString()));
    } else {
      auto mesh = std::make_shared<TriangleMesh>();
      mesh->path = path;
      size_t triangles = 0;
      for (unsigned m = 0; m < scene->mNumMeshes; ++m) triangles += scene->mMeshes[m]->mNumFaces;
      const double max_triangles = limit("SSCS_MAX_MESH_TRIANGLES", kMaxMeshTriangles);
      if (static_cast<double>(triangles) > max_triangles) {
        diag.error(where, fmt::format("mesh '{}' has {} triangles, above the limit of {:.0f} (raise it with "
                                      "SSCS_MAX_MESH_TRIANGLES, or simplify the mesh)", path, triangles, max_triangles));
        meshes_[path] = nullptr;
        return nullptr;
      }
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
      auto bad = std::find_if(mesh->vertices.begin(), mesh->vertices.end(), [](const Eigen::Vector3d& v) {
        return !v.allFinite() || v.cwiseAbs().maxCoeff() > kMaxLengthSi;
      });
      if (mesh->triangles.empty()) {
        diag.error(where, fmt::format("mesh '{}' has no triangles", path));
      } else if (bad != mesh->vertices.end()) {
        diag.error(where, fmt::format("mesh '{}' has a vertex that is {} (vertex {}: {} {} {})", path,
                                      bad->allFinite() ? fmt::format("beyond {:g} units from its origin", kMaxLengthSi) : "not a number",
                                      bad - mesh->vertices.begin() + 1, bad->x(), bad->y(), bad->z()));
      } else {
        result = std::move(mesh);
      }
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
