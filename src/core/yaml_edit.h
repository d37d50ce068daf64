#pragma once
/// Editing a YAML file's top-level keys while keeping the rest of its text (comments, layout):
/// how a run writes the vault and scenario it used into resolved/ with their paths and
/// overrides pinned.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/yaml_tree.h"

namespace sscs::yaml {

/// A top-level key and the YAML text (flow style, one line) of its new value; nullopt drops it.
using TopLevelChange = std::pair<std::string, std::optional<std::string>>;

/// `text` (the source of `root`, a mapping) with each change applied: an existing key's entry
/// (its lines, up to the next top-level key, keeping the comment and blank lines that end it)
/// becomes `key: value`; a new key is added at the end. A flow-style root (`{...}`) is written
/// again in flow style (its comments are lost).
std::string replace_top_level(std::string_view text, Node root, const std::vector<TopLevelChange>& changes);

/// A node in YAML flow style: `{a: 1, b: [x, "y z"]}`. Quoted scalars are double-quoted again.
std::string to_flow(Node node);

/// A string as a YAML flow scalar: plain when it can be, else double-quoted.
std::string flow_scalar(std::string_view s);

}  // namespace sscs::yaml
