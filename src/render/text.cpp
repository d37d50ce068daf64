#include "render/text.h"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <cstdlib>
#include <stdexcept>

#include <fmt/format.h>

namespace sscs {

namespace {

/// Code points of UTF-8 text (invalid bytes become U+FFFD).
std::u32string decode_utf8(const std::string& s) {
  std::u32string out;
  for (size_t i = 0; i < s.size();) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    int n = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    if (n == 0 || i + n > s.size()) {
      out.push_back(0xFFFD);
      ++i;
      continue;
    }
    char32_t cp = n == 1 ? c : c & (0xFF >> (n + 1));
    for (int k = 1; k < n; ++k) cp = (cp << 6) | (static_cast<unsigned char>(s[i + k]) & 0x3F);
    out.push_back(cp);
    i += n;
  }
  return out;
}

}  // namespace

std::string default_font_path() {
  if (const char* f = std::getenv("SSCS_FONT")) return f;
  return "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
}

struct Font::Impl {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
};

Font::Font(const std::string& path, int pixel_height) : impl_(std::make_unique<Impl>()) {
  if (FT_Init_FreeType(&impl_->library)) throw std::runtime_error("FreeType could not start");
  if (FT_New_Face(impl_->library, path.c_str(), 0, &impl_->face)) {
    FT_Done_FreeType(impl_->library);
    throw std::runtime_error(fmt::format("cannot load the label font '{}' (Debian package fonts-dejavu-core; or set SSCS_FONT)", path));
  }
  FT_Set_Pixel_Sizes(impl_->face, 0, static_cast<FT_UInt>(pixel_height));
}

Font::~Font() {
  FT_Done_Face(impl_->face);
  FT_Done_FreeType(impl_->library);
}

int Font::ascent() const { return static_cast<int>(impl_->face->size->metrics.ascender >> 6); }

int Font::width(const std::string& text) const {
  int w = 0;
  for (char32_t cp : decode_utf8(text))
    if (!FT_Load_Char(impl_->face, cp, FT_LOAD_DEFAULT)) w += static_cast<int>(impl_->face->glyph->advance.x >> 6);
  return w;
}

void Font::draw(Image& image, int x, int y, const std::string& text, const uint8_t rgb[3]) const {
  FT_Face face = impl_->face;
  for (char32_t cp : decode_utf8(text)) {
    if (FT_Load_Char(face, cp, FT_LOAD_RENDER)) continue;
    const FT_Bitmap& bm = face->glyph->bitmap;
    const int left = x + face->glyph->bitmap_left, top = y - face->glyph->bitmap_top;
    for (unsigned r = 0; r < bm.rows; ++r)
      for (unsigned c = 0; c < bm.width; ++c) {
        int px = left + static_cast<int>(c), py = top + static_cast<int>(r);
        if (px < 0 || py < 0 || px >= image.width || py >= image.height) continue;
        const unsigned a = bm.buffer[r * bm.pitch + c];
        uint8_t* p = &image.rgb[(static_cast<size_t>(py) * image.width + px) * 3];
        for (int k = 0; k < 3; ++k) p[k] = static_cast<uint8_t>((p[k] * (255 - a) + rgb[k] * a + 127) / 255);
      }
    x += static_cast<int>(face->glyph->advance.x >> 6);
  }
}

}  // namespace sscs
