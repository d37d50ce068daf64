#pragma once
/// Texture images of visual meshes (PNG through libpng, JPEG through libjpeg), read to colour a
/// mesh's triangles: sscs draws a textured triangle in the texel under its centre.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace sscs {

/// The most pixels a texture may have (a 8192 x 8192 image); a larger one is not read.
inline constexpr double kMaxTexturePixels = 8192.0 * 8192.0;

/// A decoded texture: 8-bit RGB, rows from the top (as images are stored).
struct Texture {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  /// The texel at texture coordinates (u, v) as 0x1RRGGBB: repeated outside [0, 1), v = 0 the
  /// bottom row (assimp's convention for every format it reads).
  uint32_t at(double u, double v) const;
};

/// Decodes a PNG or JPEG image held in `bytes`; nullopt with `why` set when it is neither, is
/// corrupt or is larger than kMaxTexturePixels.
std::optional<Texture> decode_texture(const std::string& bytes, std::string& why);

}  // namespace sscs
