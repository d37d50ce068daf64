#pragma once
/// Rendered images and PNG files (libpng, fast compression settings).
#include <cstdint>
#include <string>
#include <vector>

namespace sscs {

/// 8-bit RGB, rows from the top.
struct Image {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  const uint8_t* pixel(int x, int y) const { return &rgb[(static_cast<size_t>(y) * width + x) * 3]; }
};

/// Encodes `image` as PNG (zlib level 1, the `up` filter: a fraction of the default's time for
/// files ~20 % larger). Throws std::runtime_error on libpng errors.
std::string encode_png(const Image& image);
/// Decodes an 8-bit RGB or RGBA PNG (tests, replay comparisons). Throws on anything else.
Image decode_png(const std::string& bytes);

}  // namespace sscs
