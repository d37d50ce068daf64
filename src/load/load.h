#pragma once
/// The load stage: YAML files -> spec structs (what the user wrote, with source marks).
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/source.h"
#include "load/spec.h"

namespace sscs {

/// Reads a file into `sources`; on failure reports at `where` (the mark of the reference naming
/// it, or none for a file named on the command line) and returns 0.
uint32_t read_source(const std::string& path, Sources& sources, Diagnostics& diag, SourceMark where = {});

/// Loads a vault file. Returns nullopt when the file could not be parsed at all; otherwise the
/// spec, with every problem found reported to `diag`.
std::optional<VaultSpec> load_vault(const std::string& path, Sources& sources, Diagnostics& diag);

/// Loads a vault already registered in `sources` (tests load vaults from strings this way).
std::optional<VaultSpec> load_vault(uint32_t file, Sources& sources, Diagnostics& diag);

/// Loads one type-library file (`library/types/<type>.yaml`). A device with `urdf:` gets its
/// parts from that file, `package://` references resolved through `package_paths`.
std::optional<TypeSpec> load_type(const std::string& path, Sources& sources, Diagnostics& diag,
                                  SourceMark where = {}, const std::vector<std::string>& package_paths = {});

/// Loads a type already registered in `sources` as `file`; `path` is where its relative files
/// (meshes, a URDF) are resolved from (a plugin's type: the plugin's shared object).
std::optional<TypeSpec> load_type(uint32_t file, const std::string& path, Sources& sources, Diagnostics& diag,
                                  const std::vector<std::string>& package_paths = {});


/// Whether the file `rel`, named in type file `type_file`, does not exist where
/// resolve_mesh_path() looks; if so reports "<what> 'rel' does not exist (looked for A, from the
/// type file's folder, and B, from its library folder)" at `where`.
bool missing_reference(const std::string& what, const std::string& type_file, const std::string& rel, SourceMark where,
                       Diagnostics& diag);

/// Fills a device's parts from its URDF file (`device.urdf`, named in type file `type_file`):
/// links become parts, joints joints, inertials masses, collision (else visual) shapes geometry.
/// Problems (errors, and warnings of what was skipped) go to `device.import_problems`, at the
/// `urdf:` key or, for what is wrong inside the URDF, at its line in the URDF (read into
/// `sources`): reported where the type is used, so one broken robot does not break its folder.
void load_urdf(DeviceSpec& device, const std::string& type_file, const std::vector<std::string>& package_paths,
               Sources& sources);

/// Adds the collisions a MoveIt SRDF (`device.srdf`, beside the URDF) disables to the device's
/// allowed collisions; the file is read into `sources`, so its problems are located in it. They
/// go to `device.import_problems`, like the URDF's.
void load_srdf(DeviceSpec& device, const std::string& type_file, Sources& sources);

}  // namespace sscs
