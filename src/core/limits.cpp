#include "core/limits.h"

#include <cmath>
#include <cstdlib>

namespace sscs {

double limit(const char* env, double fallback) {
  const char* text = std::getenv(env);
  if (!text || !*text) return fallback;
  char* end = nullptr;
  double v = std::strtod(text, &end);
  return end && *end == '\0' && std::isfinite(v) && v > 0 ? v : fallback;
}

uintmax_t limit_bytes(const char* env, double fallback_mb) { return static_cast<uintmax_t>(limit(env, fallback_mb) * 1e6); }

}  // namespace sscs
