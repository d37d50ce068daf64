#include "core/files.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

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

std::string commit_dir(const std::string& tmp, const std::string& path) {
  std::error_code ec;
  if (fs::exists(path, ec)) fs::remove_all(path, ec);
  fs::rename(tmp, path, ec);
  return ec ? fmt::format("cannot move the output into '{}': {}", path, ec.message()) : "";
}

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
