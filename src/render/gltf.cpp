#include "render/gltf.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <map>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/digest.h"
#include "core/files.h"
#include "core/names.h"
#include "geometry/export.h"
#include "model/device.h"
#include "render/camera_path.h"

namespace sscs {

namespace {

using json = nlohmann::json;

constexpr int kFloat = 5126;        // componentType FLOAT
constexpr int kArrayBuffer = 34962;  // bufferView target ARRAY_BUFFER

/// sRGB (what files write: "#RRGGBB") to linear, as glTF's baseColorFactor is.
double linear(float c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

bool finite(const Eigen::Isometry3d& X) { return X.matrix().allFinite(); }

json translation(const Eigen::Isometry3d& X) { return {X.translation().x(), X.translation().y(), X.translation().z()}; }

json rotation(const Eigen::Isometry3d& X) {
  Eigen::Quaterniond q(X.linear());
  q.normalize();
  return {q.x(), q.y(), q.z(), q.w()};
}

/// A node's transform fields (none at the identity).
void place(json& node, const Eigen::Isometry3d& X) {
  if (!X.translation().isZero(0)) node["translation"] = translation(X);
  if (!X.linear().isIdentity(0)) node["rotation"] = rotation(X);
}

/// The camera's pose: the inverse of the renderer's view (it looks down its -z with +y up on the
/// image, as glTF's camera does), so a file's camera films what the frames show.
Eigen::Isometry3d camera_pose(const Camera& c) { return Eigen::Isometry3d(view_matrix(c).inverse()); }

/// The binary buffer and the accessors into it.
class Buffer {
 public:
  explicit Buffer(json& doc) : doc_(doc) {}
  const std::string& bytes() const { return bin_; }

  /// Interleaved position + normal floats: a view and its two accessors (POSITION with bounds).
  std::pair<int, int> vertices(const std::vector<float>& pn) {
    const size_t count = pn.size() / 6;
    Eigen::Vector3f lo = Eigen::Vector3f::Constant(INFINITY), hi = Eigen::Vector3f::Constant(-INFINITY);
    for (size_t v = 0; v < count; ++v)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], pn[6 * v + c]);
        hi[c] = std::max(hi[c], pn[6 * v + c]);
      }
    const int view = add_view(pn.data(), pn.size() * sizeof(float), 24);
    json& acc = doc_["accessors"];
    acc.push_back({{"bufferView", view}, {"byteOffset", 0}, {"componentType", kFloat}, {"count", count}, {"type", "VEC3"},
                   {"min", {lo.x(), lo.y(), lo.z()}}, {"max", {hi.x(), hi.y(), hi.z()}}});
    acc.push_back({{"bufferView", view}, {"byteOffset", 12}, {"componentType", kFloat}, {"count", count}, {"type", "VEC3"}});
    return {static_cast<int>(acc.size()) - 2, static_cast<int>(acc.size()) - 1};
  }

  /// Tightly packed floats, `width` a row: an accessor of type `type` (with bounds when `bounds`:
  /// animation inputs need them).
  int floats(const std::vector<float>& values, int width, const char* type, bool bounds = false) {
    const int view = add_view(values.data(), values.size() * sizeof(float), 0);
    json a = {{"bufferView", view}, {"componentType", kFloat}, {"count", values.size() / width}, {"type", type}};
    if (bounds) {
      a["min"] = json::array();
      a["max"] = json::array();
      for (int c = 0; c < width; ++c) {
        float lo = INFINITY, hi = -INFINITY;
        for (size_t i = c; i < values.size(); i += width) {
          lo = std::min(lo, values[i]);
          hi = std::max(hi, values[i]);
        }
        a["min"].push_back(lo);
        a["max"].push_back(hi);
      }
    }
    doc_["accessors"].push_back(a);
    return static_cast<int>(doc_["accessors"].size()) - 1;
  }

 private:
  int add_view(const void* data, size_t size, int stride) {
    while (bin_.size() % 4) bin_.push_back('\0');
    json view = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", size}};
    if (stride) {
      view["byteStride"] = stride;
      view["target"] = kArrayBuffer;
    }
    bin_.append(static_cast<const char*>(data), size);
    doc_["bufferViews"].push_back(view);
    return static_cast<int>(doc_["bufferViews"].size()) - 1;
  }

  json& doc_;
  std::string bin_;
};

/// The nodes whose pose the animation moves: a node, and its pose at every sample.
struct Track {
  int node;
  std::vector<Eigen::Isometry3d> X;
};

bool moves(const std::vector<Eigen::Isometry3d>& X) {
  for (const Eigen::Isometry3d& x : X)
    if ((x.matrix() - X.front().matrix()).cwiseAbs().maxCoeff() > 1e-9) return true;
  return false;
}

}  // namespace

std::vector<std::string> object_model_keys(const Workcell& wc, const GeometryModel& geometry) {
  const std::vector<char> container = containers(wc);
  std::vector<std::string> keys(wc.objects.size());
  // A mesh by its content (a new check reads it again, at another address), once a mesh.
  std::map<const TriangleMesh*, std::string> digests;
  auto mesh_digest = [&](const TriangleMesh& m) -> const std::string& {
    auto [it, fresh] = digests.try_emplace(&m);
    if (fresh) {
      std::string bytes = m.path;
      bytes.append(reinterpret_cast<const char*>(m.vertices.data()), m.vertices.size() * sizeof(Eigen::Vector3d));
      bytes.append(reinterpret_cast<const char*>(m.triangles.data()), m.triangles.size() * sizeof(Eigen::Vector3i));
      bytes.append(reinterpret_cast<const char*>(m.triangle_rgb.data()), m.triangle_rgb.size() * sizeof(uint32_t));
      for (const std::string& image : m.images) bytes += "|" + image;
      it->second = sha256_hex(bytes);
    }
    return it->second;
  };
  auto pose = [](std::string& out, const Eigen::Isometry3d& X) {
    const Eigen::Matrix<double, 3, 4> m = X.matrix().topRows<3>();
    out.append(reinterpret_cast<const char*>(m.data()), sizeof(double) * 12);  // exact: any change is a change
  };
  for (size_t o = 0; o < wc.objects.size(); ++o) {
    const ObjectGeometry& g = geometry.objects[o];
    std::string& k = keys[o];
    k = fmt::format("{}|{}|{}|{}|", wc.objects[o].name, wc.types[wc.objects[o].type].name, container[o] != 0, wc.objects[o].color);
    for (int t : wc.lineage(wc.objects[o].type)) k += wc.types[t].name + ",";
    pose(k, g.X_world_object);
    if (g.device)
      for (size_t p = 0; p < g.device->parts.size(); ++p) {
        k += "|" + g.device->parts[p].name + "|" + g.device->parts[p].color + "|";
        pose(k, g.X_object_part[p]);
      }
    for (const Shape& s : g.drawn_shapes()) {
      k += fmt::format("|{}|{}|{}|{}|{}|{}|{}|", static_cast<int>(s.kind), fmt::join(s.box_size, ","), s.radius, s.length,
                       fmt::join(s.scale, ","), s.color, s.part);
      if (s.mesh) k += mesh_digest(*s.mesh);
      pose(k, s.X_object_shape);
    }
  }
  return keys;
}

Eigen::AlignedBox3d scene_bounds(const GeometryModel& geometry) {
  Eigen::AlignedBox3d bounds;
  for (const ObjectGeometry& g : geometry.objects) bounds.extend(g.bbox_world);
  return bounds;
}

std::vector<NamedCamera> vault_cameras(const Workcell& wc, const GeometryModel& geometry) {
  std::vector<NamedCamera> out;
  for (const auto& [name, key] : wc.cameras)
    out.push_back({name, CameraPath({key}).at(0, ScenePose::of(geometry), scene_bounds(geometry), 16.0 / 9.0)});
  return out;
}

Expected<std::string> gltf_file(const Workcell& wc, const GeometryModel& geometry, const GltfScene& scene, bool binary) {
  json doc;
  doc["asset"] = {{"version", "2.0"}, {"generator", fmt::format("sscs {}", SSCS_VERSION)}};
  doc["scene"] = 0;
  doc["nodes"] = json::array();
  doc["meshes"] = json::array();
  doc["materials"] = json::array();
  doc["accessors"] = json::array();
  doc["bufferViews"] = json::array();
  Buffer buffer(doc);
  json& nodes = doc["nodes"];
  auto add_node = [&](json node) {
    nodes.push_back(std::move(node));
    return static_cast<int>(nodes.size()) - 1;
  };
  // z up (sscs) to y up (glTF): a quarter turn about x.
  const double h = std::sqrt(0.5);
  const int root = add_node({{"name", wc.name.empty() ? "sscs" : wc.name}, {"rotation", {-h, 0, 0, h}}, {"children", json::array()},
                             {"extras", {{"sscs", {{"vault", wc.name}}}}}});

  const std::vector<char> container = containers(wc);
  std::map<std::pair<std::string, bool>, int> materials;  // (colour, container) -> index
  auto material = [&](const std::string& color, bool space) {
    auto [it, fresh] = materials.try_emplace({color, space}, static_cast<int>(materials.size()));
    if (fresh) {
      auto [r, g, b] = color_rgb(color, {0.7f, 0.7f, 0.7f});
      json m = {{"name", color.empty() ? std::string("default") : color},
                {"pbrMetallicRoughness", {{"baseColorFactor", {linear(r), linear(g), linear(b), space ? 0.15 : 1.0}},
                                          {"metallicFactor", 0.0}, {"roughnessFactor", 0.85}}}};
      if (space) {
        m["alphaMode"] = "BLEND";
        m["doubleSided"] = true;
        m["name"] = color + " (container)";
      }
      doc["materials"].push_back(m);
    }
    return it->second;
  };
  std::map<std::string, int> meshes;  // shape key + material -> mesh
  std::vector<Track> tracks;
  const SceneAnimation* anim = scene.animation;
  // The run sampled once: the moving objects' poses and their parts', and the camera.
  std::map<int, std::vector<Eigen::Isometry3d>> object_at;
  std::map<int, std::vector<std::vector<Eigen::Isometry3d>>> parts_at;
  std::vector<Camera> camera_at;
  if (anim)
    for (double t : anim->times) {
      const ScenePose pose = anim->at(t);
      for (int o : anim->moving) {
        // Checked here, not where a channel is written: a pose of NaN never "moves".
        bool ok = finite(pose.X_world_object[o]);
        for (const Eigen::Isometry3d& X : pose.X_object_part[o]) ok = ok && finite(X);
        if (!ok) return Unexpected{fmt::format("{} at {} s: its pose is not a finite number", wc.objects[o].name, t)};
        object_at[o].push_back(pose.X_world_object[o]);
        parts_at[o].push_back(pose.X_object_part[o]);
      }
      if (anim->camera) camera_at.push_back(anim->camera(t, pose));
    }

  for (size_t o = 0; o < wc.objects.size(); ++o) {
    if (!scene.only.empty() && (o >= scene.only.size() || !scene.only[o])) continue;
    const ObjectGeometry& g = geometry.objects[o];
    const std::string& name = wc.objects[o].name;
    if (!finite(g.X_world_object)) return Unexpected{fmt::format("{}: its pose is not a finite number", name)};
    json lineage = json::array();  // the type and those it extends (a viewer's "every wall")
    for (int t : wc.lineage(wc.objects[o].type)) lineage.push_back(wc.types[t].name);
    json node = {{"name", name},
                 {"extras", {{"sscs", {{"object", name}, {"type", wc.types[wc.objects[o].type].name}, {"lineage", lineage},
                                       {"container", container[o] != 0}}}}}};
    place(node, g.X_world_object);
    const int object_node = add_node(node);
    nodes[root]["children"].push_back(object_node);
    // Part nodes (devices), each at its pose in the object's frame.
    std::vector<int> part_node;
    if (g.device)
      for (size_t p = 0; p < g.device->parts.size(); ++p) {
        const std::string& part = g.device->parts[p].name;
        if (!finite(g.X_object_part[p])) return Unexpected{fmt::format("{}.{}: its pose is not a finite number", name, part)};
        json pn = {{"name", name + "." + part}, {"extras", {{"sscs", {{"object", name}, {"part", part}}}}}};
        place(pn, g.X_object_part[p]);
        part_node.push_back(add_node(pn));
        nodes[object_node]["children"].push_back(part_node.back());
      }
    for (const Shape& s : g.drawn_shapes()) {
      const int part = g.device ? s.part : -1;
      const std::string& part_color = part >= 0 ? g.device->parts[part].color : std::string();
      const int mat = material(!s.color.empty() ? s.color : part_color.empty() ? wc.objects[o].color : part_color, container[o] != 0);
      auto [it, fresh] = meshes.try_emplace(fmt::format("{}|{}", shape_key(s), mat), static_cast<int>(doc["meshes"].size()));
      if (fresh) {
        Shape local = s;
        local.X_object_shape.setIdentity();
        const std::vector<float> pn = shaded_triangles(tessellate(local));
        for (float v : pn)
          if (!std::isfinite(v)) return Unexpected{fmt::format("{}: a vertex of its shape is not a finite number", name)};
        if (pn.empty()) {
          meshes.erase(it);
          continue;  // a shape with no triangles draws nothing (glTF has no empty primitives)
        }
        auto [position, normal] = buffer.vertices(pn);
        doc["meshes"].push_back({{"primitives", {{{"attributes", {{"POSITION", position}, {"NORMAL", normal}}}, {"material", mat}}}}});
      }
      const Eigen::Isometry3d X = part >= 0 ? g.X_object_part[part].inverse() * s.X_object_shape : s.X_object_shape;
      if (!finite(X)) return Unexpected{fmt::format("{}: a shape's pose is not a finite number", name)};
      json sn = {{"mesh", it->second}};
      place(sn, X);
      const int shape_node = add_node(sn);
      nodes[part >= 0 ? part_node[part] : object_node]["children"].push_back(shape_node);
    }
    if (nodes[object_node]["children"].empty()) nodes[object_node].erase("children");
    for (int p : part_node)
      if (nodes[p].contains("children") && nodes[p]["children"].empty()) nodes[p].erase("children");
    // What the run moved: the object in the world, its parts in its frame.
    if (auto moved = object_at.find(static_cast<int>(o)); moved != object_at.end()) {
      Track object_track{object_node, std::move(moved->second)};
      if (moves(object_track.X)) tracks.push_back(std::move(object_track));
      for (size_t p = 0; p < part_node.size(); ++p) {
        Track part_track{part_node[p], {}};
        for (const auto& parts : parts_at[static_cast<int>(o)]) part_track.X.push_back(parts.at(p));
        if (moves(part_track.X)) tracks.push_back(std::move(part_track));
      }
    }
  }

  // Cameras: the vault's still views, then the run's (animated when it moves).
  std::vector<NamedCamera> still = scene.cameras;
  doc["cameras"] = json::array();
  auto add_camera = [&](const std::string& name, const Camera& c, double aspect) {
    if (!c.eye.allFinite() || !c.target.allFinite() || !std::isfinite(c.fov))
      return fmt::format("camera '{}': its eye, target or fov is not a finite number", name);
    doc["cameras"].push_back({{"name", name},
                              {"type", "perspective"},
                              {"perspective", {{"yfov", c.fov * M_PI / 180}, {"aspectRatio", aspect}, {"znear", 0.05}}}});
    json cn = {{"name", name}, {"camera", static_cast<int>(doc["cameras"].size()) - 1}, {"extras", {{"sscs", {{"camera", name}}}}}};
    place(cn, camera_pose(c));
    const int node = add_node(cn);
    nodes[root]["children"].push_back(node);
    return std::string();
  };
  for (const NamedCamera& c : still)
    if (std::string err = add_camera(c.name, c.camera, 16.0 / 9.0); !err.empty()) return Unexpected{err};
  if (!camera_at.empty()) {
    if (std::string err = add_camera("run", camera_at.front(), anim->aspect); !err.empty()) return Unexpected{err};
    Track camera_track{static_cast<int>(nodes.size()) - 1, {}};
    for (const Camera& c : camera_at) {
      if (!c.eye.allFinite() || !c.target.allFinite()) return Unexpected{"the run's camera: its eye or target is not a finite number"};
      camera_track.X.push_back(camera_pose(c));
    }
    if (moves(camera_track.X)) tracks.push_back(std::move(camera_track));
  }
  if (doc["cameras"].empty()) doc.erase("cameras");

  // The run: one animation, its samples at the log's rows.
  if (anim && !anim->times.empty()) {
    std::vector<float> times;
    for (double t : anim->times) {
      if (!std::isfinite(t)) return Unexpected{"a time of the run is not a finite number"};
      times.push_back(static_cast<float>(t));
    }
    for (size_t i = 1; i < times.size(); ++i)
      if (!(times[i] > times[i - 1]))
        return Unexpected{fmt::format("the run's times do not increase at {} s (samples closer than a float tells apart)", times[i])};
    json a = {{"name", "run"}, {"channels", json::array()}, {"samplers", json::array()}};
    if (!tracks.empty()) {
      const int input = buffer.floats(times, 1, "SCALAR", /*bounds=*/true);
      for (const Track& track : tracks) {
        std::vector<float> xyz, quat;
        Eigen::Quaterniond previous(1, 0, 0, 0);
        for (size_t i = 0; i < track.X.size(); ++i) {
          if (!finite(track.X[i])) return Unexpected{fmt::format("{} at {} s: its pose is not a finite number",
                                                                 nodes[track.node]["name"].get<std::string>(), times[i])};
          for (int c = 0; c < 3; ++c) xyz.push_back(static_cast<float>(track.X[i].translation()[c]));
          Eigen::Quaterniond q(track.X[i].linear());
          q.normalize();
          if (i > 0 && q.dot(previous) < 0) q.coeffs() = -q.coeffs();  // the short way round
          previous = q;
          for (double c : {q.x(), q.y(), q.z(), q.w()}) quat.push_back(static_cast<float>(c));
        }
        for (const auto& [path, values, width, type] :
             {std::tuple{"translation", &xyz, 3, "VEC3"}, std::tuple{"rotation", &quat, 4, "VEC4"}}) {
          const int output = buffer.floats(*values, width, type);
          a["samplers"].push_back({{"input", input}, {"output", output}, {"interpolation", "LINEAR"}});
          a["channels"].push_back({{"sampler", static_cast<int>(a["samplers"].size()) - 1}, {"target", {{"node", track.node}, {"path", path}}}});
        }
      }
      doc["animations"] = json::array({a});
    }
    nodes[root]["extras"]["sscs"]["duration"] = anim->times.back();
  }

  doc["scenes"] = json::array({{{"name", wc.name.empty() ? "sscs" : wc.name}, {"nodes", {root}}}});
  for (const char* key : {"meshes", "materials", "accessors", "bufferViews"})
    if (doc[key].empty()) doc.erase(key);
  const std::string& bin = buffer.bytes();
  if (!bin.empty()) {
    doc["buffers"] = json::array({{{"byteLength", bin.size()}}});
    if (!binary) doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64(bin);
  }
  std::string text = doc.dump();
  if (!binary) return text + "\n";

  // GLB: a 12-byte header, the JSON chunk (padded with spaces), the binary chunk (with zeros).
  while (text.size() % 4) text.push_back(' ');
  std::string padded = bin;
  while (padded.size() % 4) padded.push_back('\0');
  auto u32 = [](std::string& out, uint32_t v) {
    char b[4];
    std::memcpy(b, &v, 4);  // GLB is little-endian, as every machine sscs builds on
    out.append(b, 4);
  };
  std::string out;
  const size_t total = 12 + 8 + text.size() + (padded.empty() ? 0 : 8 + padded.size());
  u32(out, 0x46546C67);  // "glTF"
  u32(out, 2);
  u32(out, static_cast<uint32_t>(total));
  u32(out, static_cast<uint32_t>(text.size()));
  u32(out, 0x4E4F534A);  // "JSON"
  out += text;
  if (!padded.empty()) {
    u32(out, static_cast<uint32_t>(padded.size()));
    u32(out, 0x004E4942);  // "BIN\0"
    out += padded;
  }
  return out;
}

std::string write_export(const Workcell& wc, const GeometryModel& geometry, const GltfScene& scene, const std::string& path) {
  const std::string ext = std::filesystem::path(path).extension().string();
  if (ext != ".glb" && ext != ".gltf") {
    if (scene.animation) return fmt::format("cannot export a run to '{}': only glTF (.glb, .gltf) holds its motion", path);
    return export_workcell(wc, geometry, path);
  }
  Expected<std::string> bytes = gltf_file(wc, geometry, scene, ext == ".glb");
  if (!bytes) return fmt::format("cannot export '{}': {}", path, bytes.error());
  return write_file_atomic(path, *bytes);
}

}  // namespace sscs
