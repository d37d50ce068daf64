#pragma once
/// The limits sscs holds hostile or broken input to (docs/reliability.md lists them all). Each
/// error that names a limit says how to raise it: an environment variable read here.
#include <cstdint>
#include <string>

namespace sscs {

/// Largest input file (a vault, type, scenario, sweep or URDF file), MB. SSCS_MAX_FILE_MB.
constexpr double kMaxInputFileMb = 256;
/// Largest mesh file, MB. SSCS_MAX_MESH_MB.
constexpr double kMaxMeshFileMb = 256;
/// Most triangles in one mesh. SSCS_MAX_MESH_TRIANGLES.
constexpr double kMaxMeshTriangles = 5e6;
/// Memory the mesh reader (assimp, in a child process) may use, MB. SSCS_MAX_MESH_READ_MB.
constexpr double kMaxMeshReadMb = 4096;
/// CPU seconds the mesh reader may use on one file: this many, plus half a second per MB of the
/// file (a 200-byte PLY can keep assimp busy for minutes). SSCS_MAX_MESH_READ_SECONDS replaces it.
constexpr double kMaxMeshReadSeconds = 10;

/// Whether RLIMIT_AS can bound a process's memory: not under AddressSanitizer, which reserves
/// terabytes of address space (the sanitizer build runs without memory limits).
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kAddressSpaceLimits = false;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
inline constexpr bool kAddressSpaceLimits = false;
#else
inline constexpr bool kAddressSpaceLimits = true;
#endif
#else
inline constexpr bool kAddressSpaceLimits = true;
#endif

/// The limit `env` sets (a number; its default when unset or empty). Garbage in one of these
/// variables is refused before any command runs (limit_environment_error).
double limit(const char* env, double fallback);
/// "" when every SSCS_MAX_* variable that is set holds a positive finite number (a whole one for
/// counts), else what is wrong with the first that does not: a typo must not quietly leave a
/// limit at its default.
std::string limit_environment_error();
/// limit() of a size in MB, in bytes.
uintmax_t limit_bytes(const char* env, double fallback_mb);

}  // namespace sscs
