#include "geometry/texture.h"

#include <png.h>
// jpeglib.h wants size_t and FILE declared before it.
#include <cstddef>
#include <cstdio>
#include <jpeglib.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>

#include <fmt/format.h>

namespace sscs {

namespace {

std::optional<Texture> too_large(double w, double h, std::string& why) {
  why = fmt::format("it has {:.0f} x {:.0f} pixels, above the limit of {:.0f} pixels", w, h, kMaxTexturePixels);
  return std::nullopt;
}

/// libpng's simplified reader: any PNG (palette, grey, 16 bit, alpha) comes out as 8-bit RGB.
std::optional<Texture> decode_png_texture(const std::string& bytes, std::string& why) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, bytes.data(), bytes.size())) {
    why = fmt::format("it is no readable PNG: {}", image.message);
    return std::nullopt;
  }
  if (double(image.width) * image.height > kMaxTexturePixels) {
    png_image_free(&image);
    return too_large(image.width, image.height, why);
  }
  image.format = PNG_FORMAT_RGB;
  Texture t;
  t.width = static_cast<int>(image.width);
  t.height = static_cast<int>(image.height);
  t.rgb.resize(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, t.rgb.data(), 0, nullptr)) {
    why = fmt::format("it is no readable PNG: {}", image.message);
    png_image_free(&image);
    return std::nullopt;
  }
  return t;
}

/// libjpeg reports errors by longjmp out of its error_exit; the message is kept first.
struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void on_jpeg_error(j_common_ptr info) {
  auto* e = reinterpret_cast<JpegError*>(info->err);
  (*info->err->format_message)(info, e->message);
  std::longjmp(e->jump, 1);
}

/// Decodes into `rgb` (sized here). False with `message` set when the file is corrupt, with an
/// empty `message` (and the size in `width`, `height`) when it is too large. Nothing whose
/// destructor matters is made between the setjmp and a longjmp.
bool decode_jpeg_into(const std::string& bytes, int& width, int& height, std::vector<uint8_t>& rgb, char* message) {
  jpeg_decompress_struct info;
  JpegError err;
  info.err = jpeg_std_error(&err.manager);
  err.manager.error_exit = on_jpeg_error;
  err.message[0] = 0;
  if (setjmp(err.jump)) {
    std::snprintf(message, JMSG_LENGTH_MAX, "%s", err.message);
    jpeg_destroy_decompress(&info);
    return false;
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  jpeg_read_header(&info, TRUE);
  info.out_color_space = JCS_RGB;
  if (double(info.image_width) * info.image_height > kMaxTexturePixels) {
    width = static_cast<int>(info.image_width);
    height = static_cast<int>(info.image_height);
    jpeg_destroy_decompress(&info);
    message[0] = 0;
    return false;
  }
  jpeg_start_decompress(&info);
  width = static_cast<int>(info.output_width);
  height = static_cast<int>(info.output_height);
  rgb.resize(static_cast<size_t>(width) * height * 3);
  while (info.output_scanline < info.output_height) {
    JSAMPROW row = rgb.data() + static_cast<size_t>(info.output_scanline) * width * 3;
    jpeg_read_scanlines(&info, &row, 1);
  }
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);
  return true;
}

std::optional<Texture> decode_jpeg_texture(const std::string& bytes, std::string& why) {
  Texture t;
  char message[JMSG_LENGTH_MAX] = {};
  if (decode_jpeg_into(bytes, t.width, t.height, t.rgb, message)) return t;
  if (message[0] == 0) return too_large(t.width, t.height, why);
  why = fmt::format("it is no readable JPEG: {}", message);
  return std::nullopt;
}

}  // namespace

uint32_t Texture::at(double u, double v) const {
  if (width <= 0 || height <= 0 || !std::isfinite(u) || !std::isfinite(v)) return 0;
  u -= std::floor(u);
  v -= std::floor(v);
  const int x = std::clamp(static_cast<int>(u * width), 0, width - 1);
  const int y = std::clamp(static_cast<int>((1 - v) * height), 0, height - 1);
  const uint8_t* p = &rgb[(static_cast<size_t>(y) * width + x) * 3];
  return 0x1000000u | uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2];
}

std::optional<Texture> decode_texture(const std::string& bytes, std::string& why) {
  if (bytes.size() >= 8 && std::equal(bytes.begin(), bytes.begin() + 8, "\x89PNG\r\n\x1a\n")) return decode_png_texture(bytes, why);
  if (bytes.size() >= 3 && static_cast<unsigned char>(bytes[0]) == 0xff && static_cast<unsigned char>(bytes[1]) == 0xd8)
    return decode_jpeg_texture(bytes, why);
  why = "it is neither a PNG nor a JPEG image, the two sscs reads";
  return std::nullopt;
}

}  // namespace sscs
