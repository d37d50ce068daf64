#include "core/data_dirs.h"

#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace sscs {

std::string data_dir(std::string_view name) {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    fs::path installed = exe.parent_path().parent_path() / "share" / "sscs" / name;
    if (fs::is_directory(installed, ec)) return installed.string();
  }
  return (fs::path(SSCS_SOURCE_DIR) / name).string();
}

std::string standard_library_dir() {
  if (const char* env = std::getenv("SSCS_LIBRARY"); env && *env) return env;
  return data_dir("library");
}

std::string schema_path(std::string_view kind) {
  return (fs::absolute(data_dir("schemas")) / fmt::format("{}.schema.json", kind)).lexically_normal().string();
}

std::string with_schema_modeline(const std::string& text, std::string_view kind) {
  if (text.find("yaml-language-server: $schema=") != std::string::npos) return text;
  return fmt::format("# yaml-language-server: $schema={}\n{}", schema_path(kind), text);
}

}  // namespace sscs
