#include "chromatag/generator/cairo_util.h"

#include <cairo-pdf.h>

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "chromatag/base/input_file.h"

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

namespace {

void AppendPngBytes(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))
      ->append(reinterpret_cast<const char*>(data), length);
}

}  // namespace

std::string EncodePng(cairo_surface_t* surface, double dpi) {
  cairo_surface_flush(surface);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) return {};
  const cairo_format_t format = cairo_image_surface_get_format(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  if (data == nullptr || (format != CAIRO_FORMAT_RGB24 && format != CAIRO_FORMAT_ARGB32)) return {};
  const int width = cairo_image_surface_get_width(surface);
  const int height = cairo_image_surface_get_height(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  const bool alpha = format == CAIRO_FORMAT_ARGB32;
  const int channels = alpha ? 4 : 3;
  const auto per_metre = static_cast<png_uint_32>(std::lround(dpi / 0.0254));

  std::string png;
  std::vector<png_byte> row(static_cast<size_t>(width) * channels);
  png_structp writer = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = writer ? png_create_info_struct(writer) : nullptr;
  if (info == nullptr) {
    png_destroy_write_struct(&writer, nullptr);
    return {};
  }
  // libpng reports errors by longjmp: nothing below holds a destructor that
  // the jump would skip (png and row live outside).
  if (setjmp(png_jmpbuf(writer))) {
    png_destroy_write_struct(&writer, &info);
    return {};
  }
  png_set_write_fn(writer, &png, AppendPngBytes, nullptr);
  png_set_IHDR(writer, info, width, height, 8, alpha ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  // The resolution, so that the page prints at its size (Cairo writes none).
  png_set_pHYs(writer, info, per_metre, per_metre, PNG_RESOLUTION_METER);
  png_write_info(writer, info);
  for (int y = 0; y < height; ++y) {
    const auto* pixels = reinterpret_cast<const uint32_t*>(data + static_cast<size_t>(y) * stride);
    for (int x = 0; x < width; ++x) {
      // Cairo's pixels: native-endian 0xAARRGGBB, colour premultiplied by alpha.
      const uint32_t p = pixels[x];
      const uint32_t a = alpha ? p >> 24 : 255;
      uint32_t rgb[3] = {(p >> 16) & 0xff, (p >> 8) & 0xff, p & 0xff};
      png_byte* out = &row[static_cast<size_t>(x) * channels];
      for (int c = 0; c < 3; ++c) {
        out[c] = static_cast<png_byte>(a == 255 ? rgb[c] : a == 0 ? 0 : (rgb[c] * 255 + a / 2) / a);
      }
      if (alpha) out[3] = static_cast<png_byte>(a);
    }
    png_write_row(writer, row.data());
  }
  png_write_end(writer, info);
  png_destroy_write_struct(&writer, &info);
  return png;
}

std::string RasterPageProblem(double width_mm, double height_mm, double dpi) {
  const double w_in = width_mm / 25.4, h_in = height_mm / 25.4;
  // Rounded as the drawing's surface is made.
  const double w_px = std::round(w_in * dpi), h_px = std::round(h_in * dpi);
  const auto budget = static_cast<double>(kMaxImagePixels);
  if (w_px * h_px <= budget && std::max(w_px, h_px) <= kMaxRasterSidePx) return "";
  const double fit = std::floor(std::min(std::sqrt(budget / std::max(w_in * h_in, 1e-12)),
                                         kMaxRasterSidePx / std::max({w_in, h_in, 1e-12})));
  const auto whole = [](double value) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.0f", value);
    return std::string(buffer);
  };
  return "a page of " + whole(width_mm) + " x " + whole(height_mm) + " mm at " + whole(dpi) +
         " dpi is " + whole(w_px) + " x " + whole(h_px) + " pixels (" +
         whole(w_px * h_px / (1 << 20)) + " Mpx), over the limit of " +
         (w_px * h_px > budget ? std::to_string(kMaxImagePixels >> 20) + " Mpx"
                               : whole(kMaxRasterSidePx) + " pixels a side") +
         "; " + (fit >= 1.0 ? "at most " + whole(fit) + " dpi fits" : "no dpi fits");
}

std::string RenderPdf(double width, double height, const std::string& title, int pages,
                      const std::function<void(cairo_t*, int)>& draw) {
  std::string bytes;
  cairo_surface_t* surface =
      cairo_pdf_surface_create_for_stream(AppendToString, &bytes, width, height);
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, title.c_str());
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATE_DATE, "");
  cairo_t* cr = cairo_create(surface);
  for (int page = 0; page < pages; ++page) {
    draw(cr, page);
    cairo_show_page(cr);
  }
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  cairo_surface_destroy(surface);
  return bytes;
}

std::string RenderPng(int width, int height, double dpi,
                      const std::function<void(cairo_t*)>& draw) {
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(surface);
    return "";
  }
  cairo_t* cr = cairo_create(surface);
  draw(cr);
  cairo_destroy(cr);
  std::string bytes;
  if (dpi > 0) {
    bytes = EncodePng(surface, dpi);
  } else {
    cairo_surface_write_to_png_stream(surface, AppendToString, &bytes);
  }
  cairo_surface_destroy(surface);
  return bytes;
}

}  // namespace chromatag
