#pragma once
/// Writing output files atomically: write under a temporary name beside the target, then rename,
/// so that a reader (or a CI step) never sees a half-written report, frame or model.
#include <string>

namespace sscs {

/// A temporary path in the target's folder that keeps the target's extension (exporters pick
/// formats by it): "dir/.name.tmp<pid>.ext".
std::string temp_path_for(const std::string& path);

/// Renames `tmp` over `path`; on failure removes `tmp`. Returns an error message or "".
std::string commit_file(const std::string& tmp, const std::string& path);

/// Writes `content` to `path` atomically. Returns an error message or "".
std::string write_file_atomic(const std::string& path, const std::string& content);

}  // namespace sscs
