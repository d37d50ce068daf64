#pragma once
/// What `sscs types` shows of a type beyond its file: an instance at its default attributes, so a
/// user sees where things are (frames, bounds, the tool's reach) without reading type files.
#include <memory>
#include <ostream>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "pipeline/compile_vault.h"
#include "plugin/plugins.h"

namespace sscs {

struct TypeInstance {
  std::string unbuilt;  ///< why there is no instance at the defaults (a required attribute), or ""
  Eigen::AlignedBox3d bounds;  ///< of its geometry, in the type's frame; empty without geometry
  /// The type's named frames (own and inherited) and, for devices, the tool, in the type's frame.
  std::vector<std::pair<std::string, Eigen::Isometry3d>> frames;
  struct Mesh {
    std::string file;  ///< relative to the type file's folder
    bool closed = false;
  };
  std::vector<Mesh> meshes;
  std::optional<Eigen::AlignedBox3d> reach;  ///< devices: the tool's envelope over the joint ranges
  /// Devices: how fast each joint moves in a run (the type's values, else the defaults).
  struct JointMotion {
    std::string name;
    JointType type = JointType::Fixed;
    double speed = 0, acceleration = 0;  ///< SI
    bool speed_given = false, acceleration_given = false;
  };
  std::vector<JointMotion> joints;
  std::shared_ptr<const Workcell> workcell;  ///< the instance (for a picture of it), unless unbuilt
};

const char* joint_type_name(JointType t);
/// "[1.2, 0, 0.851]" (6 significant digits; inf where unbounded).
std::string vec_text(const Eigen::Vector3d& v);
/// A frame's orientation in degrees, or nothing when it is the type's own.
std::optional<Eigen::Vector3d> frame_rpy_deg(const Eigen::Isometry3d& X);

/// Compiles one instance of `type` at its defaults (with the library already loaded into
/// `sources`) and reads its geometry. A type that cannot be instanced says why in `unbuilt`;
/// what stopped it inside the library's files (a mesh that cannot be read, an SRDF naming no
/// link, a home outside the limits: problems a vault using the type meets) is also reported to
/// `problems` at its place, with the warnings of the import.
TypeInstance instance_at_defaults(const std::shared_ptr<const std::vector<ObjectType>>& library, const ObjectType& type,
                                  const CompileOptions& options, Sources& sources, Diagnostics& problems);

/// Writes what `sscs types` shows: each type of the loaded library `types` (sorted by name) with
/// its attributes, where an instance at its defaults puts its frames, bounds and meshes, a
/// device's parts, tool and reach; then the constraint kinds and the plugins' constraint
/// classes. Text, or JSON (`json`). The instances' problems in the library go to `problems`.
void write_type_listing(std::ostream& out, std::vector<ObjectType> types, const PluginSet& plugins, const CompileOptions& instance_options,
                        bool json, Sources& sources, Diagnostics& problems);


}  // namespace sscs
