#pragma once
/// Text on images through FreeType, with a Debian font (DejaVu Sans): labels of contact sheets.
#include <memory>
#include <string>

#include "render/image.h"

namespace sscs {

/// The font file used: $SSCS_FONT, else DejaVu Sans from fonts-dejavu-core.
std::string default_font_path();

class Font {
 public:
  /// Throws std::runtime_error naming the file when FreeType cannot load it.
  Font(const std::string& path, int pixel_height);
  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  /// Draws UTF-8 `text` with its baseline at y, starting at x, blending the glyphs' coverage.
  void draw(Image& image, int x, int y, const std::string& text, const uint8_t rgb[3]) const;
  /// The advance width of `text` in pixels.
  int width(const std::string& text) const;
  int ascent() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sscs
