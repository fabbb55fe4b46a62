#include "chromatag/generator/cairo_util.h"

#include <zlib.h>

#include <cmath>
#include <cstdint>

namespace chromatag {

void DrawText(cairo_t* cr, double x, double y, double size, const std::string& text, bool bold) {
  cairo_select_font_face(cr, kLabelFont, CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_move_to(cr, x, y);
  cairo_show_text(cr, text.c_str());
}

cairo_status_t AppendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

std::string EncodePng(cairo_surface_t* surface, double dpi) {
  std::string png;
  cairo_surface_write_to_png_stream(surface, AppendToString, &png);
  const uint32_t per_metre = static_cast<uint32_t>(std::lround(dpi / 0.0254));
  std::string chunk = "pHYs";
  for (int repeat = 0; repeat < 2; ++repeat) {
    for (int shift = 24; shift >= 0; shift -= 8) {
      chunk.push_back(static_cast<char>(per_metre >> shift));
    }
  }
  chunk.push_back(1);  // Unit: metre.
  const uint32_t crc =
      crc32(0, reinterpret_cast<const Bytef*>(chunk.data()), static_cast<uInt>(chunk.size()));
  std::string bytes = {0, 0, 0, 9};  // Data length.
  bytes += chunk;
  for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(static_cast<char>(crc >> shift));
  constexpr size_t kAfterIhdr = 8 + 25;  // Signature, then IHDR's 4 + 4 + 13 + 4 bytes.
  png.insert(kAfterIhdr, bytes);
  return png;
}

}  // namespace chromatag
