#pragma once
/// The compile stage: a VaultSpec and its gathered inputs (inputs/inputs.h) -> an immutable Workcell.
/// It reads nothing from the file system.
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "compile/workcell.h"
#include "core/diagnostics.h"
#include "load/spec.h"
#include "inputs/inputs.h"
#include "plugin/plugins.h"

namespace sscs {

/// Resolves a library's type files (`extends` in dependency order, attributes inherited) into
/// types. `wanted` (when given): only these types, and those they extend, get their templates
/// compiled (`shaped`); every type gets its name, attributes and flags (a check of a one-drum
/// vault compiled the geometry and parts of all 29 standard types: two thirds of its time). A
/// plugin's type that does not resolve throws PluginError naming the plugin.
std::vector<ObjectType> build_library(const LibraryInputs& inputs, Sources& sources, Diagnostics& diag,
                                      const std::set<std::string>* wanted = nullptr);

/// Compiles a vault from its gathered inputs (gather_vault), reading nothing from the file system.
/// Returns nullopt when any input error was reported.
std::optional<Workcell> compile(const VaultSpec& spec, const VaultInputs& inputs, const CompileOptions& options, Sources& sources,
                                Diagnostics& diag);

/// What `OBJECT.member` reads of a compiled object (`height`, `location.x`, `orientation.yaw`,
/// `bbox.max.y`): the operand a check or a sweep metric evaluates, or nullopt with `why` (the
/// message, naming the reference). Bounding boxes only when `allow_bbox` (not in attribute values).
std::optional<Operand> member_operand(const Workcell& wc, int object, std::string_view member, bool allow_bbox, std::string* why);

}  // namespace sscs
