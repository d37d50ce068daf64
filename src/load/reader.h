#pragma once
/// Helpers shared by the vault and type loaders: strict maps, scalars, names and vectors.
/// One mechanism for every file kind, so unknown keys, wrong kinds and bad names read alike.
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostics.h"
#include "core/yaml_tree.h"
#include "load/spec.h"

namespace sscs::load {

/// Reads a mapping strictly: every key must be asked for by take()/require() before finish(),
/// or it is reported as unknown, with the closest known key as a suggestion.
class MapReader {
 public:
  /// `what` names the mapping in messages ("object", "bound constraint").
  MapReader(yaml::Node node, std::string what, Diagnostics& diag);
  bool ok() const { return ok_; }
  yaml::Node node() const { return node_; }
  SourceMark mark() const { return node_.mark(); }
  const std::string& what() const { return what_; }

  /// The value under `key`, or an invalid node.
  yaml::Node take(std::string_view key);
  /// The value under `key`; reports "missing key" when absent.
  yaml::Node require(std::string_view key);
  bool has(std::string_view key) const { return ok_ && node_.find(key).valid(); }
  /// The keys not asked for, in file order (for object attributes).
  std::vector<std::pair<yaml::Node, yaml::Node>> rest();
  /// Reports every key not asked for.
  void finish();

 private:
  yaml::Node node_;
  std::string what_;
  Diagnostics& diag_;
  bool ok_ = false;
  std::vector<std::string_view> known_;  ///< keys are string literals or static names
};

/// Reports "expected X for Y, found Z" at the node.
void expected(Diagnostics& diag, yaml::Node node, std::string_view expectation, std::string_view what);

/// A scalar value (number, unit literal, expression or string). Absent node -> !present.
Scalar scalar(yaml::Node node, std::string_view what, Diagnostics& diag);
/// A plain string (e.g. a description).
std::string text(yaml::Node node, std::string_view what, Diagnostics& diag);
/// A valid name (letter first, then letters, digits, '_' or '-').
std::string name(yaml::Node node, std::string_view what, Diagnostics& diag);
/// `true`/`false`.
bool boolean(yaml::Node node, std::string_view what, Diagnostics& diag, bool fallback = false);
/// A sequence of exactly three scalars (absent node -> three absent scalars).
std::array<Scalar, 3> vec3(yaml::Node node, std::string_view what, Diagnostics& diag);
/// A camera: `eye` and `target`, or `orbit: {target, radius, azimuth, elevation}`, and `fov`;
/// a scenario's keyframes also have `t`.
CameraKeySpec read_camera(yaml::Node node, Diagnostics& diag, bool keyframe);
/// `{xyz: [..], rpy: [..]}` read from `reader` (the keys live beside others).
PoseSpec pose(MapReader& reader, Diagnostics& diag);
/// `repeat:` read from `reader`, if it is there.
std::optional<RepeatSpec> repeat(MapReader& reader, Diagnostics& diag);
/// A scalar or a sequence of scalars.
std::vector<Scalar> scalar_list(yaml::Node node, std::string_view what, Diagnostics& diag);
/// Geometry list of a type or part.
std::vector<GeometrySpec> geometry_list(yaml::Node node, Diagnostics& diag);
/// Checks the `sscs: 1` format version key of a file's top-level mapping.
void check_version(MapReader& root, Diagnostics& diag);
/// Free-form YAML (plugin args) as JSON.
nlohmann::ordered_json to_json(yaml::Node node);

}  // namespace sscs::load
