#include "geometry/export.h"

#include "core/files.h"
#include "core/names.h"
#include "model/device.h"

#include <assimp/Exporter.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>

#include <fmt/format.h>

namespace sscs {

namespace {

void add_quad(TriangleMesh& m, int a, int b, int c, int d) {
  m.triangles.emplace_back(a, b, c);
  m.triangles.emplace_back(a, c, d);
}

TriangleMesh box_mesh(const Eigen::Vector3d& size) {
  TriangleMesh m;
  Eigen::Vector3d h = size / 2;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  // Outward-facing (counter-clockwise seen from outside).
  add_quad(m, 0, 2, 3, 1);  // -z
  add_quad(m, 4, 5, 7, 6);  // +z
  add_quad(m, 0, 1, 5, 4);  // -y
  add_quad(m, 2, 6, 7, 3);  // +y
  add_quad(m, 0, 4, 6, 2);  // -x
  add_quad(m, 1, 3, 7, 5);  // +x
  return m;
}

TriangleMesh cylinder_mesh(double r, double length, int n = 32) {
  TriangleMesh m;
  for (int i = 0; i < n; ++i) {
    double a = 2 * std::numbers::pi * i / n;
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), -length / 2);
    m.vertices.emplace_back(r * std::cos(a), r * std::sin(a), length / 2);
  }
  int bottom = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, -length / 2);
  m.vertices.emplace_back(0, 0, length / 2);
  for (int i = 0; i < n; ++i) {
    int j = (i + 1) % n;
    add_quad(m, 2 * i, 2 * j, 2 * j + 1, 2 * i + 1);
    m.triangles.emplace_back(bottom, 2 * j, 2 * i);
    m.triangles.emplace_back(bottom + 1, 2 * i + 1, 2 * j + 1);
  }
  return m;
}

TriangleMesh sphere_mesh(double r, int n = 32) {
  TriangleMesh m;
  int rings = n / 2;
  for (int i = 0; i <= rings; ++i) {
    double phi = std::numbers::pi * i / rings;
    for (int j = 0; j < n; ++j) {
      double theta = 2 * std::numbers::pi * j / n;
      m.vertices.emplace_back(r * std::sin(phi) * std::cos(theta), r * std::sin(phi) * std::sin(theta), r * std::cos(phi));
    }
  }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < n; ++j) {
      int a = i * n + j, b = i * n + (j + 1) % n;
      add_quad(m, a, a + n, b + n, b);
    }
  return m;
}

aiColor4D parse_color(const std::string& hex) {
  auto [r, g, b] = color_rgb(hex, {0.7f, 0.7f, 0.7f});
  return {r, g, b, 1.0f};
}

aiMatrix4x4 to_ai(const Eigen::Isometry3d& X) {
  const Eigen::Matrix4d& M = X.matrix();
  return aiMatrix4x4(static_cast<ai_real>(M(0, 0)), static_cast<ai_real>(M(0, 1)), static_cast<ai_real>(M(0, 2)),
                     static_cast<ai_real>(M(0, 3)), static_cast<ai_real>(M(1, 0)), static_cast<ai_real>(M(1, 1)),
                     static_cast<ai_real>(M(1, 2)), static_cast<ai_real>(M(1, 3)), static_cast<ai_real>(M(2, 0)),
                     static_cast<ai_real>(M(2, 1)), static_cast<ai_real>(M(2, 2)), static_cast<ai_real>(M(2, 3)), 0, 0, 0, 1);
}

}  // namespace

TriangleMesh tessellate(const Shape& s) {
  TriangleMesh m;
  switch (s.kind) {
    case Shape::Kind::Box: m = box_mesh(s.box_size); break;
    case Shape::Kind::Cylinder: m = cylinder_mesh(s.radius, s.length); break;
    case Shape::Kind::Sphere: m = sphere_mesh(s.radius); break;
    case Shape::Kind::Mesh:
      m = *s.mesh;
      for (Eigen::Vector3d& v : m.vertices) v = v.cwiseProduct(s.scale);
      break;
  }
  for (Eigen::Vector3d& v : m.vertices) v = s.X_object_shape * v;
  return m;
}

std::vector<float> shaded_triangles(const TriangleMesh& m) {
  const size_t nt = m.triangles.size();
  std::vector<Eigen::Vector3d> face(nt);
  std::vector<std::vector<size_t>> faces_of(m.vertices.size());
  for (size_t t = 0; t < nt; ++t) {
    const Eigen::Vector3i& tri = m.triangles[t];
    Eigen::Vector3d n = (m.vertices[tri[1]] - m.vertices[tri[0]]).cross(m.vertices[tri[2]] - m.vertices[tri[0]]);
    face[t] = n.norm() > 0 ? n.normalized() : Eigen::Vector3d::UnitZ();
    for (int k = 0; k < 3; ++k) faces_of[tri[k]].push_back(t);
  }
  const double crease = std::cos(30 * std::numbers::pi / 180);
  std::vector<float> out;
  out.reserve(nt * 18);
  for (size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      int v = m.triangles[t][k];
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      for (size_t f : faces_of[v])
        if (face[f].dot(face[t]) >= crease) n += face[f];
      n = n.norm() > 0 ? n.normalized() : face[t];
      for (int c = 0; c < 3; ++c) out.push_back(static_cast<float>(m.vertices[v][c]));
      for (int c = 0; c < 3; ++c) out.push_back(static_cast<float>(n[c]));
    }
  return out;
}

std::string shape_key(const Shape& s) {
  return fmt::format("{}|{}|{}|{}|{}|{}", static_cast<int>(s.kind), fmt::join(s.box_size, ","), s.radius, s.length,
                     static_cast<const void*>(s.mesh.get()), fmt::join(s.scale, ","));
}

std::string export_workcell(const Workcell& wc, const GeometryModel& geometry, const std::string& path) {
  namespace fs = std::filesystem;
  std::string ext = fs::path(path).extension().string();
  std::string format = ext == ".obj" ? "obj" : ext == ".stl" ? "stlb" : "";
  if (format.empty()) return fmt::format("cannot export '{}': expected a .glb, .gltf, .obj or .stl file", path);

  aiScene scene;  // owns everything below; its destructor frees the arrays
  scene.mRootNode = new aiNode(wc.name);
  size_t n = wc.objects.size();
  // One material per object; device parts with their own colour get one each, after those.
  std::vector<std::pair<std::string, std::string>> materials;  // name, colour
  for (size_t i = 0; i < n; ++i) materials.emplace_back(wc.objects[i].name, wc.objects[i].color);
  if (materials.empty()) materials.emplace_back("default", "");
  std::map<std::pair<size_t, int>, unsigned> part_material;
  for (size_t i = 0; i < n; ++i)
    if (const auto& d = geometry.objects[i].device)
      for (size_t p = 0; p < d->parts.size(); ++p)
        if (!d->parts[p].color.empty()) {
          part_material[{i, static_cast<int>(p)}] = static_cast<unsigned>(materials.size());
          materials.emplace_back(wc.objects[i].name + "." + d->parts[p].name, d->parts[p].color);
        }
  // Shapes with a colour of their own (a URDF visual's material): a material per object and colour.
  std::map<std::pair<size_t, std::string>, unsigned> shape_material;
  for (size_t i = 0; i < n; ++i)
    for (const Shape& s : geometry.objects[i].drawn_shapes())
      if (!s.color.empty() && !shape_material.count({i, s.color})) {
        shape_material[{i, s.color}] = static_cast<unsigned>(materials.size());
        materials.emplace_back(fmt::format("{}.{}", wc.objects[i].name, s.color.substr(1)), s.color);
      }
  scene.mNumMaterials = static_cast<unsigned>(materials.size());
  scene.mMaterials = new aiMaterial*[scene.mNumMaterials];
  for (unsigned i = 0; i < scene.mNumMaterials; ++i) {
    scene.mMaterials[i] = new aiMaterial();
    aiString name(materials[i].first);
    scene.mMaterials[i]->AddProperty(&name, AI_MATKEY_NAME);
    aiColor4D color = parse_color(materials[i].second);
    scene.mMaterials[i]->AddProperty(&color, 1, AI_MATKEY_COLOR_DIFFUSE);
  }
  std::vector<aiMesh*> meshes;
  std::vector<aiNode*> nodes;
  for (size_t i = 0; i < n; ++i) {
    auto* node = new aiNode(wc.objects[i].name);
    node->mTransformation = to_ai(geometry.objects[i].X_world_object);
    node->mParent = scene.mRootNode;
    std::vector<unsigned> own;
    for (const Shape& s : geometry.objects[i].drawn_shapes()) {
      TriangleMesh tm = tessellate(s);
      auto* mesh = new aiMesh();
      mesh->mName = aiString(wc.objects[i].name);  // OBJ groups are named after meshes
      auto part = part_material.find({i, s.part});
      mesh->mMaterialIndex = !s.color.empty()           ? shape_material.at({i, s.color})
                             : part != part_material.end() ? part->second
                                                           : static_cast<unsigned>(i);
      mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
      mesh->mNumVertices = static_cast<unsigned>(tm.vertices.size());
      mesh->mVertices = new aiVector3D[mesh->mNumVertices];
      for (size_t v = 0; v < tm.vertices.size(); ++v)
        mesh->mVertices[v] = aiVector3D(static_cast<ai_real>(tm.vertices[v].x()), static_cast<ai_real>(tm.vertices[v].y()),
                                        static_cast<ai_real>(tm.vertices[v].z()));
      mesh->mNumFaces = static_cast<unsigned>(tm.triangles.size());
      mesh->mFaces = new aiFace[mesh->mNumFaces];
      for (size_t f = 0; f < tm.triangles.size(); ++f) {
        aiFace& face = mesh->mFaces[f];
        face.mNumIndices = 3;
        face.mIndices = new unsigned[3]{static_cast<unsigned>(tm.triangles[f].x()), static_cast<unsigned>(tm.triangles[f].y()),
                                        static_cast<unsigned>(tm.triangles[f].z())};
      }
      own.push_back(static_cast<unsigned>(meshes.size()));
      meshes.push_back(mesh);
    }
    node->mNumMeshes = static_cast<unsigned>(own.size());
    if (!own.empty()) {
      node->mMeshes = new unsigned[own.size()];
      std::copy(own.begin(), own.end(), node->mMeshes);
    }
    nodes.push_back(node);
  }
  scene.mRootNode->mNumChildren = static_cast<unsigned>(nodes.size());
  if (!nodes.empty()) {
    scene.mRootNode->mChildren = new aiNode*[nodes.size()];
    std::copy(nodes.begin(), nodes.end(), scene.mRootNode->mChildren);
  }
  scene.mNumMeshes = static_cast<unsigned>(meshes.size());
  if (!meshes.empty()) {
    scene.mMeshes = new aiMesh*[meshes.size()];
    std::copy(meshes.begin(), meshes.end(), scene.mMeshes);
  }

  // STL has no nodes: bake the world transforms into the vertices.
  unsigned steps = format == "stlb" ? static_cast<unsigned>(aiProcess_PreTransformVertices) : 0u;
  // OBJ writes a .mtl beside the file, named after it: export into a fresh
  // folder under the final names, then move every file into place.
  fs::path target(path);
  fs::path stage = temp_path_for((target.parent_path() / "export").string());
  std::error_code ec;
  fs::create_directories(stage, ec);
  if (ec) return fmt::format("cannot write '{}': {}", path, ec.message());
  Assimp::Exporter exporter;
  std::string error;
  if (exporter.Export(&scene, format, (stage / target.filename()).string(), steps) != AI_SUCCESS)
    error = fmt::format("cannot export '{}': {}", path, exporter.GetErrorString());
  // The main file last, so that once it appears its companions are there.
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(stage, ec))
    if (entry.path().filename() != target.filename()) files.push_back(entry.path());
  files.push_back(stage / target.filename());
  for (const fs::path& f : files) {
    if (!error.empty()) break;
    error = commit_file(f.string(), (target.parent_path() / f.filename()).string());
  }
  fs::remove_all(stage, ec);
  return error;
}

}  // namespace sscs
