#include "core/archive.h"

#include <zip.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace sscs {

namespace {

constexpr time_t kBundleTime = 315532800;  // 1980-01-01 00:00 UTC, the earliest zip time

std::string zip_message(int code) {
  zip_error_t e;
  zip_error_init_with_code(&e, code);
  std::string s = zip_error_strerror(&e);
  zip_error_fini(&e);
  return s;
}

}  // namespace

std::string zip_folder(const std::string& folder, const std::string& zip_path) {
  std::vector<std::string> files;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(folder, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec))
    if (it->is_regular_file()) files.push_back(fs::relative(it->path(), folder).generic_string());
  if (ec) return fmt::format("cannot list '{}': {}", folder, ec.message());
  std::sort(files.begin(), files.end());

  int code = 0;
  zip_t* za = zip_open(zip_path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &code);
  if (!za) return fmt::format("cannot create '{}': {}", zip_path, zip_message(code));
  for (const std::string& name : files) {
    std::string path = (fs::path(folder) / name).string();
    zip_source_t* src = zip_source_file(za, path.c_str(), 0, -1);
    zip_int64_t index = src ? zip_file_add(za, name.c_str(), src, ZIP_FL_ENC_UTF_8) : -1;
    if (index < 0) {
      if (src) zip_source_free(src);
      std::string msg = fmt::format("cannot add '{}' to '{}': {}", name, zip_path, zip_strerror(za));
      zip_discard(za);
      return msg;
    }
    bool png = fs::path(name).extension() == ".png";  // already compressed
    zip_set_file_compression(za, static_cast<zip_uint64_t>(index), png ? ZIP_CM_STORE : ZIP_CM_DEFLATE, png ? 0 : 6);
    zip_file_set_mtime(za, static_cast<zip_uint64_t>(index), kBundleTime, 0);
    zip_file_set_external_attributes(za, static_cast<zip_uint64_t>(index), 0, ZIP_OPSYS_UNIX, 0100644u << 16);
  }
  if (zip_close(za) != 0) {
    std::string msg = fmt::format("cannot write '{}': {}", zip_path, zip_strerror(za));
    zip_discard(za);
    return msg;
  }
  return "";
}

Expected<std::string> read_zip_entry(const std::string& zip_path, const std::string& name) {
  int code = 0;
  std::unique_ptr<zip_t, decltype(&zip_discard)> za(zip_open(zip_path.c_str(), ZIP_RDONLY, &code), &zip_discard);
  if (!za) return Unexpected{fmt::format("{}: not a readable zip archive ({})", zip_path, zip_message(code))};
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat(za.get(), name.c_str(), 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
    return Unexpected{fmt::format("{}: no {} in this archive", zip_path, name)};
  std::unique_ptr<zip_file_t, decltype(&zip_fclose)> f(zip_fopen(za.get(), name.c_str(), 0), &zip_fclose);
  std::string bytes(st.size, '\0');
  if (!f || zip_fread(f.get(), bytes.data(), st.size) != static_cast<zip_int64_t>(st.size))
    return Unexpected{fmt::format("{}: cannot read {}: {}", zip_path, name, zip_strerror(za.get()))};
  return bytes;
}

std::string unzip_into(const std::string& zip_path, const std::string& dir, const std::vector<std::string>& skip) {
  int code = 0;
  std::unique_ptr<zip_t, decltype(&zip_discard)> za(zip_open(zip_path.c_str(), ZIP_RDONLY, &code), &zip_discard);
  if (!za) return fmt::format("{}: not a readable zip archive ({})", zip_path, zip_message(code));
  const zip_int64_t n = zip_get_num_entries(za.get(), 0);
  for (zip_int64_t i = 0; i < n; ++i) {
    const char* raw = zip_get_name(za.get(), static_cast<zip_uint64_t>(i), 0);
    if (!raw) return fmt::format("{}: entry {} has no name", zip_path, i);
    const std::string name = raw;
    if (std::any_of(skip.begin(), skip.end(), [&](const std::string& s) { return name.rfind(s, 0) == 0; })) continue;
    const fs::path rel = fs::path(name).lexically_normal();
    if (name.empty() || rel.is_absolute() || rel.empty() || *rel.begin() == "..")
      return fmt::format("{}: entry '{}' lies outside the archive's folder", zip_path, name);
    const fs::path target = fs::path(dir) / rel;
    std::error_code ec;
    if (name.back() == '/') {
      fs::create_directories(target, ec);
      if (ec) return fmt::format("cannot create '{}': {}", target.string(), ec.message());
      continue;
    }
    fs::create_directories(target.parent_path(), ec);
    if (ec) return fmt::format("cannot create '{}': {}", target.parent_path().string(), ec.message());
    std::unique_ptr<zip_file_t, decltype(&zip_fclose)> f(zip_fopen_index(za.get(), static_cast<zip_uint64_t>(i), 0), &zip_fclose);
    if (!f) return fmt::format("{}: cannot read {}: {}", zip_path, name, zip_strerror(za.get()));
    std::ofstream out(target, std::ios::binary);
    char buffer[1 << 16];
    zip_int64_t got = 0;
    while ((got = zip_fread(f.get(), buffer, sizeof buffer)) > 0) out.write(buffer, got);
    if (got < 0) return fmt::format("{}: cannot read {}: {}", zip_path, name, zip_file_strerror(f.get()));
    if (!out.flush()) return fmt::format("cannot write '{}'", target.string());
  }
  return "";
}

}  // namespace sscs
