#pragma once
// What the libFuzzer targets share: a private scratch folder, and the standard library loaded once.
// Every target feeds its input to one stage of sscs as a user's file would reach it; an input
// error is the expected outcome, a crash, hang, leak or sanitizer report is a defect.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/compile_vault.h"
#include "core/files.h"
#include "load/load.h"

namespace sscs::fuzz {

/// A folder of this process's own (removed at exit), where inputs that must be files are written.
inline const std::filesystem::path& scratch() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("sscs-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  static const struct Cleanup {
    ~Cleanup() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } cleanup;
  return dir;
}

/// Writes `bytes` to scratch()/name and returns its path.
inline std::string write_scratch(const std::string& name, const uint8_t* data, size_t size) {
  std::string path = (scratch() / name).string();
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), size);
  return path;
}

/// Reads confined to scratch(), as `sscs check` confines them to the vault's project root: the
/// files an input names (library folders, plugin folders, meshes, URDFs) go through the checks
/// of confinement too. Call once, after standard_library() (which lies outside it).
inline void confine_to_scratch() {
  static const bool done = (confine_reads({scratch().string()}), true);
  (void)done;
}

/// The standard library (SSCS_LIBRARY_DIR), loaded and resolved once per process.
inline std::shared_ptr<const std::vector<ObjectType>> standard_library() {
  static const std::shared_ptr<const std::vector<ObjectType>> library = [] {
    Sources sources;
    Diagnostics diag;
    auto types = load_library({}, sources, diag);
    if (diag.has_errors()) {
      fprintf(stderr, "fuzz: the standard library does not load:\n%s", diag.format(sources).c_str());
      abort();
    }
    return std::make_shared<const std::vector<ObjectType>>(std::move(types));
  }();
  return library;
}

}  // namespace sscs::fuzz
