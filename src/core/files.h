#pragma once
/// Writing output files atomically: write under a temporary name beside the target, then rename,
/// so that a reader (or a CI step) never sees a half-written report, frame or model.
#include <functional>
#include <ostream>
#include <string>

namespace sscs {

/// Why `path` is no file to read: "" when it is a regular file (or a link to one), else "does not
/// exist", "is a folder, not a file", "is a FIFO (named pipe), not a file", "is a device, not a
/// file" or "is a socket, not a file" (reading a FIFO would wait for ever).
std::string not_a_file(const std::string& path);

/// A temporary path in the target's folder that keeps the target's extension (exporters pick
/// formats by it): "dir/.name.tmp<pid>.ext".
std::string temp_path_for(const std::string& path);

/// Renames `tmp` over `path`; on failure removes `tmp`. Returns an error message or "".
std::string commit_file(const std::string& tmp, const std::string& path);

/// A hidden temporary folder beside a target folder (or archive): "dir/.name.tmp-<pid>". Outputs
/// made of many files are assembled there and appear with commit_dir().
std::string temp_dir_for(const std::string& path);

/// Replaces the folder `path` (if any) with `tmp`. Returns an error message or "".
std::string commit_dir(const std::string& tmp, const std::string& path);

/// Writes `content` to `path` atomically. Returns an error message or "".
std::string write_file_atomic(const std::string& path, const std::string& content);
/// The same for output written as it is produced (a streamed report): `write` fills the stream.
std::string write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace sscs
