#pragma once
/// Content digests of input files, for run summaries (OpenSSL's SHA-256), and base64 (for data
/// URIs in glTF files and HTML reports).
#include <optional>
#include <string>
#include <string_view>

namespace sscs {

/// Lower-case hex SHA-256 of `bytes`.
std::string sha256_hex(std::string_view bytes);

/// `bytes` in standard base64 (RFC 4648, padded, no line breaks).
std::string base64(std::string_view bytes);

/// The bytes of the file at `path`, or nullopt when it cannot be read.
std::optional<std::string> read_file_bytes(const std::string& path);

}  // namespace sscs
