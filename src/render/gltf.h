#pragma once
/// The workcell, and a run's motion, as one glTF 2.0 file (binary .glb, or .gltf with its
/// buffer inline): what `sscs export` writes and what the HTML reports show.
///
/// Layout (docs/export.md): a root node turns sscs' z-up world into glTF's y-up; under it one
/// node per object (named after it, at its world pose), under a device one node per part (at its
/// pose in the object's frame: `Robot1.link2`), and under those one node per drawn shape with a
/// mesh shared by every shape of the same size and colour. Each object node carries
/// `extras.sscs` = {object, type, lineage (the type and those it extends), container}; part nodes {object, part}. Containers (a room) are
/// drawn translucent. A run's motion is one animation, "run", sampled at the log's rows:
/// translation and rotation of every object and part node that moved, and of the run's camera.
#include <functional>
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "core/expected.h"
#include "geometry/geometry.h"
#include "render/camera.h"

namespace sscs {

struct NamedCamera {
  std::string name;
  Camera camera;
};

/// A run's motion for glTF, sampled at `times`: where everything was (`at`), of which only
/// the `moving` objects are read (their pose, their parts'), and the run's camera.
struct SceneAnimation {
  std::vector<double> times;                   ///< s, increasing
  std::vector<int> moving;                     ///< objects whose pose or parts may change
  std::function<ScenePose(double)> at;
  std::function<Camera(double, const ScenePose&)> camera;  ///< empty: no camera recorded
  double aspect = 16.0 / 9.0;                  ///< of the run's frames
};

struct GltfScene {
  std::vector<NamedCamera> cameras;            ///< still views (the vault's named cameras)
  const SceneAnimation* animation = nullptr;  ///< a run's motion, or none
  /// Per object, whether to write it (empty: every object): what `sscs serve` sends of a save
  /// that changed a few objects (their nodes, under the same root).
  std::vector<char> only = {};
};

/// Per object, a text that is the same exactly when gltf_file draws the object the same (its
/// name, type, pose, parts and shapes with their colours): what changed between two checks.
std::vector<std::string> object_model_keys(const Workcell& wc, const GeometryModel& geometry);

/// The world bounds of every object's geometry (what the renderer frames).
Eigen::AlignedBox3d scene_bounds(const GeometryModel& geometry);

/// The vault's named cameras as still views, at the geometry's own placement.
std::vector<NamedCamera> vault_cameras(const Workcell& wc, const GeometryModel& geometry);

/// The file's bytes: GLB when `binary`, else glTF JSON with the buffer as a data URI. An error
/// when a pose, a vertex or a time is not a finite number (it would be written as null).
Expected<std::string> gltf_file(const Workcell& wc, const GeometryModel& geometry, const GltfScene& scene, bool binary);

/// `sscs export`: the scene to `path` by its extension, .glb or .gltf (gltf_file), .obj or .stl
/// (export_workcell: no motion, no cameras). Written to a temporary name, then renamed. The
/// error message, or "" on success.
std::string write_export(const Workcell& wc, const GeometryModel& geometry, const GltfScene& scene, const std::string& path);

}  // namespace sscs
