#pragma once
/// The pipeline's first steps for a vault: its inputs gathered (inputs/, the one stage that reads
/// the file system for a compile), then compiled (compile/, which never does).
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "compile/compile.h"

namespace sscs {

/// Gathers the inputs of the vault `spec` and compiles it. Returns nullopt when any input error
/// was reported; a plugin that cannot be used throws PluginError.
std::optional<Workcell> compile_vault(const VaultSpec& spec, const CompileOptions& options, Sources& sources, Diagnostics& diag);

/// Loads and compiles the vault file at `path`.
std::optional<Workcell> compile_file(const std::string& path, const CompileOptions& options, Sources& sources, Diagnostics& diag);

/// Gathers and builds a type library: the standard library's folder and `dirs` (gather_library),
/// with the plugins' types; `wanted` as build_library's.
std::vector<ObjectType> load_library(const std::vector<std::pair<std::string, SourceMark>>& dirs, Sources& sources,
                                     Diagnostics& diag, const std::vector<std::string>& package_paths = {},
                                     const std::vector<PluginType>& plugin_types = {},
                                     const std::set<std::string>* wanted = nullptr);

}  // namespace sscs
