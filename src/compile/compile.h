#pragma once
/// The compile stage: a VaultSpec and its type library -> an immutable Workcell.
#include <optional>
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "load/spec.h"

namespace sscs {

struct CompileOptions {
  std::vector<std::string> library_dirs;  ///< extra type folders (--library), after the vault's own
  std::vector<std::string> package_paths;  ///< --package-path: roots of `package://` references in URDF
  std::vector<std::string> plugin_dirs;   ///< --plugins (checked to exist; loading comes with the plugin issue)
  std::vector<std::pair<std::string, std::string>> overrides;  ///< --set NAME=VALUE
};

/// The standard library folder: $SSCS_LIBRARY, else <exe>/../share/sscs/library, else the source tree's.
std::string standard_library_dir();

/// Loads every type file of the standard library and of `dirs`, resolving inheritance.
/// `where` marks the reference to a folder that does not exist.
/// `package_paths` resolve `package://` references of URDF devices.
std::vector<ObjectType> load_library(const std::vector<std::pair<std::string, SourceMark>>& dirs, Sources& sources,
                                     Diagnostics& diag, const std::vector<std::string>& package_paths = {});

/// Compiles a vault. Returns nullopt when any input error was reported.
std::optional<Workcell> compile(const VaultSpec& spec, const CompileOptions& options, Sources& sources,
                                Diagnostics& diag);

/// Loads and compiles the vault file at `path`.
std::optional<Workcell> compile_file(const std::string& path, const CompileOptions& options, Sources& sources,
                                     Diagnostics& diag);

}  // namespace sscs
