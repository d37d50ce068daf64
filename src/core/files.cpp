#include "core/files.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <map>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

namespace sscs {

std::string not_a_file(const std::string& path) {
  std::error_code ec;
  const std::filesystem::file_status st = std::filesystem::status(path, ec);
  switch (st.type()) {
    case std::filesystem::file_type::regular: return "";
    case std::filesystem::file_type::directory: return "is a folder, not a file";
    case std::filesystem::file_type::fifo: return "is a FIFO (named pipe), not a file";
    case std::filesystem::file_type::block:
    case std::filesystem::file_type::character: return "is a device, not a file";
    case std::filesystem::file_type::socket: return "is a socket, not a file";
    default: return "does not exist";
  }
}

namespace fs = std::filesystem;

namespace {
struct Confinement {
  bool active = false;
  std::vector<fs::path> roots;  ///< canonical; the first is the project root
};
Confinement& confinement() {
  static Confinement c;
  return c;
}

/// `path` as an absolute path with symbolic links resolved (as far as it exists).
fs::path resolved(const fs::path& path) {
  std::error_code ec;
  fs::path abs = fs::absolute(path, ec);
  fs::path canon = fs::weakly_canonical(abs, ec);
  return ec ? abs.lexically_normal() : canon;
}

bool within(const fs::path& path, const fs::path& root) {
  auto p = path.begin();
  for (auto r = root.begin(); r != root.end(); ++r, ++p) {
    if (r->empty() && std::next(r) == root.end()) return true;  // a trailing separator
    if (p == path.end() || *p != *r) return false;
  }
  return true;
}
}  // namespace

void confine_reads(const std::vector<std::string>& roots) {
  Confinement& c = confinement();
  c.active = true;
  c.roots.clear();
  for (const std::string& r : roots)
    if (!r.empty()) c.roots.push_back(resolved(r));
}

std::string join_path(const std::string& dir, const std::string& rel) {
  fs::path r(rel);
  if (r.is_absolute()) return r.string();
  const fs::path joined = (dir.empty() ? fs::path(".") : fs::path(dir)) / r;
  const fs::path normal = joined.lexically_normal();
  // Without a ".." no symbolic link can make the lexical form differ.
  if (std::find(joined.begin(), joined.end(), fs::path("..")) == joined.end()) return normal.string();
  return resolved(joined) == resolved(normal) ? normal.string() : joined.string();
}

std::string outside_roots(const std::string& path) {
  const Confinement& c = confinement();
  if (!c.active || c.roots.empty()) return "";
  const fs::path real = resolved(path);
  for (const fs::path& root : c.roots)
    if (within(real, root)) return "";
  std::error_code ec;
  const fs::path written = fs::absolute(path, ec).lexically_normal();
  const std::string how = "(run with --root naming a folder that holds it, or --allow-outside-root)";
  for (const fs::path& root : c.roots)
    if (within(written, root))
      return fmt::format("leads outside the project root {} through a symbolic link (to {}) {}", c.roots[0].string(),
                         real.string(), how);
  return fmt::format("is outside the project root {} {}", c.roots[0].string(), how);
}

std::string resolve_mesh_path(const std::string& type_file, const std::string& rel) {
  fs::path p(rel);
  if (p.is_absolute()) return p.string();
  const fs::path folder = fs::path(type_file).parent_path();
  std::string beside = join_path(folder.string(), rel);
  std::error_code ec;
  if (fs::exists(beside, ec)) return beside;
  return join_path(folder.parent_path().string(), rel);
}

std::vector<std::string> ros_package_path() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("ROS_PACKAGE_PATH")) {
    std::stringstream ss(env);
    for (std::string dir; std::getline(ss, dir, ':');)
      if (!dir.empty()) out.push_back(dir);
  }
  return out;
}

namespace {

/// The <name> of the ROS package whose manifest is `manifest`, or "".
std::string package_name(const fs::path& manifest) {
  std::ifstream in(manifest);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  // The manifest's first <name> element (package.xml formats 1 to 3 put it first).
  const size_t open = s.find("<name>"), close = s.find("</name>", open);
  if (open == std::string::npos || close == std::string::npos) return "";
  std::string name = s.substr(open + 6, close - open - 6);
  const size_t b = name.find_first_not_of(" \t\r\n"), e = name.find_last_not_of(" \t\r\n");
  return b == std::string::npos ? "" : name.substr(b, e - b + 1);
}

/// Every package below `root` (to `depth` levels) by its manifest's name; a package's own
/// folders are not searched further (packages do not nest), nor are hidden ones.
void index_packages(const fs::path& root, int depth, std::map<std::string, std::string>& out) {
  std::error_code ec;
  if (fs::is_regular_file(root / "package.xml", ec)) {
    if (std::string name = package_name(root / "package.xml"); !name.empty()) out.emplace(name, root.string());
    return;
  }
  if (depth == 0) return;
  std::vector<fs::path> children;
  for (fs::directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_directory(ec) && !it->path().filename().string().starts_with(".")) children.push_back(it->path());
  std::sort(children.begin(), children.end());  // the first found wins, whatever the file system's order
  for (const fs::path& child : children) index_packages(child, depth - 1, out);
}

}  // namespace

std::string find_ros_package(const std::string& root_text, const std::string& package) {
  fs::path root = fs::path(root_text).lexically_normal();
  if (root.filename().empty()) root = root.parent_path();  // DIR/ is DIR
  // Indexed once per folder: a URDF names its package for every mesh.
  static std::mutex mutex;
  static std::map<std::string, std::map<std::string, std::string>> indexes;
  std::map<std::string, std::string> index;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto [it, fresh] = indexes.try_emplace(fs::absolute(root).string());
    if (fresh) index_packages(root, 5, it->second);
    index = it->second;
  }
  if (auto found = index.find(package); found != index.end()) return found->second;
  std::error_code ec;
  if (fs::is_directory(root / package, ec)) return (root / package).string();
  if (root.filename() == package && fs::is_directory(root, ec)) return root.string();
  return "";
}

std::string not_a_readable_reference(const std::string& path) {
  if (std::string why = outside_roots(path); !why.empty()) return why;
  return not_a_file(path);
}

std::string project_root_of(const std::string& file) {
  std::error_code ec;
  fs::path folder = fs::is_directory(file, ec) ? resolved(file) : resolved(file).parent_path();
  for (fs::path p = folder; !p.empty(); p = p.parent_path()) {
    if (fs::exists(p / ".git", ec)) return p.string();
    if (p == p.parent_path()) break;
  }
  return folder.string();
}

std::string temp_path_for(const std::string& path) {
  fs::path target(path);
  return (target.parent_path() /
          fmt::format(".{}.tmp{}{}", target.stem().string(), getpid(), target.extension().string()))
      .string();
}

std::string commit_file(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (!ec) return "";
  std::remove(tmp.c_str());
  return fmt::format("cannot write '{}': {}", path, ec.message());
}

std::string temp_dir_for(const std::string& path) {
  fs::path target(path);
  return (target.parent_path() / fmt::format(".{}.tmp-{}", target.filename().string(), getpid())).string();
}

bool FileSystem::exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(fs::symlink_status(path, ec));
}
std::error_code FileSystem::rename(const std::string& from, const std::string& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  return ec;
}
std::error_code FileSystem::remove_all(const std::string& path) {
  std::error_code ec;
  fs::remove_all(path, ec);
  return ec;
}
std::error_code FileSystem::create_directories(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  return ec;
}
FileSystem& FileSystem::disk() {
  static FileSystem real;
  return real;
}

std::string commit_dir(const std::string& tmp, const std::string& path, FileSystem& files) {
  std::string aside;
  if (files.exists(path)) {
    aside = fs::path(temp_dir_for(path)).concat(".old").string();
    files.remove_all(aside);
    if (std::error_code ec = files.rename(path, aside)) {
      files.remove_all(tmp);
      return fmt::format("cannot move the output into '{}': cannot move the earlier one aside: {}", path, ec.message());
    }
  }
  if (std::error_code ec = files.rename(tmp, path)) {
    if (!aside.empty()) files.rename(aside, path);  // the earlier output stays
    files.remove_all(tmp);
    return fmt::format("cannot move the output into '{}': {}", path, ec.message());
  }
  if (!aside.empty()) files.remove_all(aside);
  return "";
}

StagedDir::StagedDir(std::string target, FileSystem& files) : target_(std::move(target)), staging_(temp_dir_for(target_)), fs_(files) {
  // Staging folders of the same target whose process is gone (killed: no destructor ran).
  const fs::path dir(staging_);
  const fs::path parent = dir.parent_path().empty() ? fs::path(".") : dir.parent_path();
  const std::string name = dir.filename().string(), stem = name.substr(0, name.rfind('-') + 1);  // ".NAME.tmp-"
  std::error_code ec;
  for (auto it = fs::directory_iterator(parent, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const std::string other = it->path().filename().string();
    if (!other.starts_with(stem)) continue;
    char* end = nullptr;
    const long pid = std::strtol(other.c_str() + stem.size(), &end, 10);
    if ((*end == '\0' || std::string_view(end) == ".old") && pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH)
      fs_.remove_all(it->path().string());
  }
  fs_.remove_all(staging_);
  if (std::error_code made = fs_.create_directories(staging_))
    throw OutputError(fmt::format("cannot create '{}': {}", staging_, made.message()));
}

StagedDir::~StagedDir() { fs_.remove_all(staging_); }

std::string StagedDir::commit() { return commit_dir(staging_, target_, fs_); }

std::string write_file(const std::string& path, std::string_view content) {
  errno = 0;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return fmt::format("cannot write '{}': {}", path, std::strerror(errno));
  bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  ok = std::fflush(f) == 0 && ok;
  int err = errno;
  ok = std::fclose(f) == 0 && ok;
  if (!ok) err = err ? err : errno;
  if (ok) return "";
  std::remove(path.c_str());
  return fmt::format("cannot write '{}': {}", path, err ? std::strerror(err) : "short write");
}

std::string write_file_atomic(const std::string& path, const std::string& content) {
  return write_file_atomic(path, [&](std::ostream& out) { out << content; });
}

std::string write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write) {
  std::string tmp = temp_path_for(path);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return fmt::format("cannot write '{}': {}", path, std::strerror(errno));
    write(out);
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      return fmt::format("cannot write '{}': {}", path, std::strerror(errno));
    }
  }
  return commit_file(tmp, path);
}

}  // namespace sscs
