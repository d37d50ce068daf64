#pragma once
/// Zip archives through libzip: a run folder packed into one bundle, and files read back out of
/// one. Bundles are reproducible: entries in sorted order with a fixed timestamp, so the same
/// run gives the same bytes.
#include <optional>
#include <string>
#include <vector>

#include "core/expected.h"

namespace sscs {

/// Packs every file under `folder` into a new zip at `zip_path` (paths relative to `folder`,
/// '/'-separated; PNG files stored, the rest deflated). Returns an error message or "".
std::string zip_folder(const std::string& folder, const std::string& zip_path);

/// The bytes of entry `name` in the zip at `zip_path`; nullopt with `error` set when the file is
/// not a readable zip or has no such entry.
Expected<std::string> read_zip_entry(const std::string& zip_path, const std::string& name);

/// Unpacks the zip at `zip_path` into the existing folder `dir`, except entries whose names
/// start with one of `skip` (a bundle's frames). An entry whose name is absolute, climbs out
/// (`..`) or is not a plain file or folder is an error: nothing is written outside `dir`.
/// Returns an error message or "".
std::string unzip_into(const std::string& zip_path, const std::string& dir, const std::vector<std::string>& skip = {});

}  // namespace sscs
