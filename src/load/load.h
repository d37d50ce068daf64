#pragma once
/// The load stage: YAML files -> spec structs (what the user wrote, with source marks).
#include <optional>
#include <string>

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

/// Loads one type-library file (`library/types/<type>.yaml`).
std::optional<TypeSpec> load_type(const std::string& path, Sources& sources, Diagnostics& diag,
                                  SourceMark where = {});

}  // namespace sscs
