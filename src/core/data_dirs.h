#pragma once
/// Where sscs finds the data it ships beside its binary: the standard type library and the JSON
/// Schemas of its file formats. An installed sscs uses <prefix>/share/sscs/<name>; a build-tree
/// binary uses the source tree's folder.
#include <string>
#include <string_view>

namespace sscs {

/// <exe>/../share/sscs/<name> when that folder exists, else <source tree>/<name>.
std::string data_dir(std::string_view name);

/// The standard library folder: $SSCS_LIBRARY, else data_dir("library").
std::string standard_library_dir();

/// The JSON Schema of a file kind ("vault", "scenario", "type", "sweep", "cameras"), as an absolute
/// path in data_dir("schemas").
std::string schema_path(std::string_view kind);

/// `text` with a `# yaml-language-server: $schema=...` line first, unless it already names a
/// schema: how files sscs writes tell an editor what they are.
std::string with_schema_modeline(const std::string& text, std::string_view kind);

}  // namespace sscs
