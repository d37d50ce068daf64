#include "render/contact_sheet.h"

#include <algorithm>

namespace sscs {

Image downscale(const Image& in, int width) {
  Image out;
  out.width = std::max(1, std::min(width, in.width));
  out.height = std::max(1, static_cast<int>(static_cast<long>(in.height) * out.width / in.width));
  out.rgb.resize(static_cast<size_t>(out.width) * out.height * 3);
  for (int y = 0; y < out.height; ++y) {
    const int y0 = y * in.height / out.height, y1 = std::max(y0 + 1, (y + 1) * in.height / out.height);
    for (int x = 0; x < out.width; ++x) {
      const int x0 = x * in.width / out.width, x1 = std::max(x0 + 1, (x + 1) * in.width / out.width);
      unsigned sum[3] = {0, 0, 0};
      for (int v = y0; v < y1; ++v)
        for (int u = x0; u < x1; ++u)
          for (int k = 0; k < 3; ++k) sum[k] += in.pixel(u, v)[k];
      const unsigned n = static_cast<unsigned>((y1 - y0) * (x1 - x0));
      for (int k = 0; k < 3; ++k) out.rgb[(static_cast<size_t>(y) * out.width + x) * 3 + k] = static_cast<uint8_t>((sum[k] + n / 2) / n);
    }
  }
  return out;
}

Image contact_sheet(const std::vector<Thumbnail>& thumbs, const Font& font, int columns) {
  constexpr int kMargin = 10, kLabel = 26;
  Image sheet;
  if (thumbs.empty()) return sheet;
  const int tw = thumbs[0].image.width, th = thumbs[0].image.height;
  const int cols = std::max(1, std::min<int>(columns, static_cast<int>(thumbs.size())));
  const int rows = (static_cast<int>(thumbs.size()) + cols - 1) / cols;
  sheet.width = kMargin + cols * (tw + kMargin);
  sheet.height = kMargin + rows * (th + kLabel + kMargin);
  sheet.rgb.assign(static_cast<size_t>(sheet.width) * sheet.height * 3, 250);
  const uint8_t ink[3] = {30, 30, 36};
  for (size_t i = 0; i < thumbs.size(); ++i) {
    const int x0 = kMargin + static_cast<int>(i % cols) * (tw + kMargin);
    const int y0 = kMargin + static_cast<int>(i / cols) * (th + kLabel + kMargin);
    const Image& t = thumbs[i].image;
    for (int y = 0; y < std::min(th, t.height); ++y)
      std::copy_n(t.pixel(0, y), 3 * std::min(tw, t.width), &sheet.rgb[(static_cast<size_t>(y0 + y) * sheet.width + x0) * 3]);
    font.draw(sheet, x0 + 2, y0 + th + 4 + font.ascent(), thumbs[i].label, ink);
  }
  return sheet;
}

}  // namespace sscs
