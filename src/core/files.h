#pragma once
/// Writing output files atomically: write under a temporary name beside the target, then rename,
/// so that a reader (or a CI step) never sees a half-written report, frame or model.
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace sscs {

/// An output that could not be written (a full disk, a folder that cannot be made): the message
/// names the path and the system's reason. Commands report it as an error (exit 2), never as an
/// internal one, and leave nothing that looks complete.
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Writes `content` to `path`, checking every byte reached the file (flushed and closed: a full
/// disk shows at the flush). For files inside a folder committed whole. Returns an error or "".
std::string write_file(const std::string& path, std::string_view content);

/// Why `path` is no file to read: "" when it is a regular file (or a link to one), else "does not
/// exist", "is a folder, not a file", "is a FIFO (named pipe), not a file", "is a device, not a
/// file" or "is a socket, not a file" (reading a FIFO would wait for ever).
std::string not_a_file(const std::string& path);

/// Confines the files and folders that input files name (meshes, URDFs and their meshes, type
/// files, libraries, plugin folders, geomodels, the vaults and scenarios of scenarios and sweeps)
/// to `roots`: the project root first (the one messages name), then folders the command line
/// named. Paths are compared after resolving symbolic links, so a link inside a root that points
/// out of it is outside. Until this is called nothing is confined (tests, library users).
void confine_reads(const std::vector<std::string>& roots);

/// "" when `path`, named in an input file, lies inside the roots of confine_reads(); else why not
/// ("is outside the project root /p (...)", "leads outside the project root /p through a symbolic link ...").
std::string outside_roots(const std::string& path);

/// Where a type file's reference to another file (a mesh, a URDF) points: beside the type file
/// if it exists there, else relative to its library folder (the one holding types/), as
/// `meshes/drum.obj` is written. Absolute paths stay.
std::string resolve_mesh_path(const std::string& type_file, const std::string& rel);

/// The folders of $ROS_PACKAGE_PATH (colon-separated; empty entries dropped): searched for
/// `package://` references after --package-path, and trusted like it.
std::vector<std::string> ros_package_path();

/// The folder of ROS package `package` under `root` (a --package-path or $ROS_PACKAGE_PATH
/// folder), as ROS finds it: `root` itself or a folder below it (at most 5 levels, as in a
/// colcon workspace's src/) whose package.xml has `<name>package</name>`; failing that, as a
/// folder name: `root/package`, or `root` when it is named `package`. Empty when none.
std::string find_ros_package(const std::string& root, const std::string& package);

/// Why a file named in an input file cannot be read: outside_roots(), else not_a_file().
std::string not_a_readable_reference(const std::string& path);

/// `rel` (a path written in an input file) against the folder `dir`, as the system resolves it:
/// `rel` itself when absolute; lexically normal ("a/./b/../c" -> "a/c") when that names the same
/// file; else joined as written, for a symbolic link before a ".." leads elsewhere than the
/// lexical form ("sec/../x" with sec -> /srv/sec is /srv/x).
std::string join_path(const std::string& dir, const std::string& rel);

/// The project root of a file (or folder) named on the command line: the top of the git work tree
/// holding it (the folder with `.git`), else its own folder (the folder itself).
std::string project_root_of(const std::string& file);

/// A temporary path in the target's folder that keeps the target's extension (exporters pick
/// formats by it): "dir/.name.tmp<pid>.ext".
std::string temp_path_for(const std::string& path);

/// Renames `tmp` over `path`; on failure removes `tmp`. Returns an error message or "".
std::string commit_file(const std::string& tmp, const std::string& path);

/// A hidden temporary folder beside a target folder (or archive): "dir/.name.tmp-<pid>". Outputs
/// made of many files are assembled there and appear with commit_dir().
std::string temp_dir_for(const std::string& path);

/// The file-system operations outputs are committed with: the real file system, or a fake in
/// tests (a rename that fails, a disk that fills). Ninja's DiskInterface is the model.
class FileSystem {
 public:
  virtual ~FileSystem() = default;
  virtual bool exists(const std::string& path);
  virtual std::error_code rename(const std::string& from, const std::string& to);
  virtual std::error_code remove_all(const std::string& path);
  virtual std::error_code create_directories(const std::string& path);
  /// The real one.
  static FileSystem& disk();
};

/// Replaces the folder `path` (if any) with `tmp`: the old folder is moved aside, `tmp` renamed
/// into place, then the old one removed; if the rename fails the old folder is put back, so
/// `path` holds the old output or the new one, never nothing. Returns an error message or "".
std::string commit_dir(const std::string& tmp, const std::string& path, FileSystem& files = FileSystem::disk());

/// An output folder assembled in a hidden staging folder beside it (temp_dir_for) and renamed into
/// place whole by commit(): nothing half-written ever stands under the target's name. The staging
/// folder starts empty (the staging folders that killed sscs processes left beside the same
/// target are removed too) and is removed when this goes unless it was committed: an error, an
/// exception or an interrupt leaves nothing behind. The one way sscs makes an output folder.
class StagedDir {
 public:
  /// Throws OutputError when the staging folder cannot be made.
  explicit StagedDir(std::string target, FileSystem& files = FileSystem::disk());
  ~StagedDir();
  StagedDir(const StagedDir&) = delete;
  StagedDir& operator=(const StagedDir&) = delete;

  const std::string& path() const { return staging_; }
  const std::string& target() const { return target_; }
  /// Moves the staging folder to the target (commit_dir). Returns an error message or ""; on an
  /// error the staging folder is removed.
  std::string commit();

 private:
  std::string target_, staging_;
  FileSystem& fs_;
};

/// Writes `content` to `path` atomically. Returns an error message or "".
std::string write_file_atomic(const std::string& path, const std::string& content);
/// The same for output written as it is produced (a streamed report): `write` fills the stream.
std::string write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write);

}  // namespace sscs
