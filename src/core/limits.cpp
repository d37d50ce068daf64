#include "core/limits.h"

#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "core/diagnostics.h"

namespace sscs {

namespace {

struct LimitVariable {
  const char* name;
  double fallback;
  const char* unit;
  bool whole;  ///< a count
};
constexpr LimitVariable kLimitVariables[] = {
    {"SSCS_MAX_FILE_MB", kMaxInputFileMb, "MB", false},
    {"SSCS_MAX_MESH_MB", kMaxMeshFileMb, "MB", false},
    {"SSCS_MAX_MESH_TRIANGLES", kMaxMeshTriangles, "triangles", true},
    {"SSCS_MAX_MESH_READ_MB", kMaxMeshReadMb, "MB", false},
    {"SSCS_MAX_MESH_READ_SECONDS", kMaxMeshReadSeconds, "s plus 0.5 s per MB of the file", false},
};

}  // namespace

std::string limit_environment_error() {
  for (const LimitVariable& v : kLimitVariables) {
    const char* text = std::getenv(v.name);
    if (!text || !*text) continue;
    char* end = nullptr;
    double x = std::strtod(text, &end);
    bool ok = end && *end == '\0' && std::isfinite(x) && x > 0 && (!v.whole || x == std::floor(x));
    if (!ok)
      return fmt::format("the environment variable {}={} is not a limit: expected a positive {}number{} (unset it for the "
                         "default, {} {})", v.name, printable(within_window(text)), v.whole ? "whole " : "",
                         v.whole ? "" : ", fractions allowed", v.fallback, v.unit);
  }
  return "";
}

double limit(const char* env, double fallback) {
  const char* text = std::getenv(env);
  if (!text || !*text) return fallback;
  char* end = nullptr;
  double v = std::strtod(text, &end);
  return end && *end == '\0' && std::isfinite(v) && v > 0 ? v : fallback;
}

uintmax_t limit_bytes(const char* env, double fallback_mb) { return static_cast<uintmax_t>(limit(env, fallback_mb) * 1e6); }

}  // namespace sscs
