#pragma once
/// The compile stage: a VaultSpec and its type library -> an immutable Workcell.
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "load/spec.h"
#include "plugin/plugins.h"

namespace sscs {

struct CompileOptions {
  std::vector<std::string> library_dirs;  ///< extra type folders (--library), after the vault's own
  std::vector<std::string> package_paths;  ///< --package-path: roots of `package://` references in URDF
  std::vector<std::string> plugin_dirs;   ///< --plugins: folders whose plugins are loaded
  bool allow_vault_plugins = false;       ///< --allow-vault-plugins: load the vault's `plugins:` folders too
  std::shared_ptr<PluginSet> plugins;     ///< where loaded plugins go (created when null)
  std::vector<std::pair<std::string, std::string>> overrides;  ///< --set NAME=VALUE
  /// The type library already loaded (a Workcell's `types` compiled from the same vault file with
  /// the same plugins): compile() then reads no type file and loads no plugin. A sweep compiles
  /// each variant this way.
  std::shared_ptr<const std::vector<ObjectType>> library;
  /// Compile the templates of every type of the library, not only those the vault's objects use
  /// (a library kept for other vaults, or variants, to reuse: a sweep's).
  bool whole_library = false;
};


/// Loads every type file of the standard library and of `dirs`, resolving inheritance.
/// `where` marks the reference to a folder that does not exist.
/// `package_paths` resolve `package://` references of URDF devices. `plugin_types` join the
/// library; one whose name the library also defines, or that does not resolve (extends an
/// unknown type, an expression naming no attribute), throws PluginError naming the plugin.
/// `wanted` (when given): only these types, and those they extend, get their templates compiled
/// (`shaped`); every type gets its name, attributes and flags (a check of a one-drum vault
/// compiled the geometry and parts of all 29 standard types: two thirds of its time).
std::vector<ObjectType> load_library(const std::vector<std::pair<std::string, SourceMark>>& dirs, Sources& sources,
                                     Diagnostics& diag, const std::vector<std::string>& package_paths = {},
                                     const std::vector<PluginType>& plugin_types = {},
                                     const std::set<std::string>* wanted = nullptr);

/// Compiles a vault. Returns nullopt when any input error was reported. Loads the plugins of
/// --plugins folders, and of the vault's `plugins:` folders when the command line allows them
/// (else an input error saying how); a plugin that cannot be used throws PluginError.
std::optional<Workcell> compile(const VaultSpec& spec, const CompileOptions& options, Sources& sources,
                                Diagnostics& diag);

/// What `OBJECT.member` reads of a compiled object (`height`, `location.x`, `orientation.yaw`,
/// `bbox.max.y`): the operand a check or a sweep metric evaluates, or nullopt with `why` (the
/// message, naming the reference). Bounding boxes only when `allow_bbox` (not in attribute values).
std::optional<Operand> member_operand(const Workcell& wc, int object, std::string_view member, bool allow_bbox, std::string* why);

/// Loads and compiles the vault file at `path`.
std::optional<Workcell> compile_file(const std::string& path, const CompileOptions& options, Sources& sources,
                                     Diagnostics& diag);

}  // namespace sscs
