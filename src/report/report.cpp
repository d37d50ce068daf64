#include "report/report.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <unistd.h>

namespace sscs {

std::string subject_names(const Workcell& wc, const CheckResult& r, const char* separator) {
  std::string out;
  for (int s : r.subjects) {
    if (!out.empty()) out += separator;
    out += wc.objects[s].name;
  }
  return out;
}


std::string write_file_atomic(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  fs::path target(path);
  std::string tmp = (target.parent_path() / ("." + target.filename().string() + fmt::format(".tmp{}", getpid()))).string();
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) return fmt::format("cannot write '{}': {}", path, std::strerror(errno));
    out << content;
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      return fmt::format("cannot write '{}': {}", path, std::strerror(errno));
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    std::remove(tmp.c_str());
    return fmt::format("cannot write '{}': {}", path, ec.message());
  }
  return "";
}

}  // namespace sscs
