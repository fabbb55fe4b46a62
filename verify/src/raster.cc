#include "chromatag/verify/raster.h"

#include <librsvg/rsvg.h>
#include <poppler/cpp/poppler-document.h>
#include <poppler/cpp/poppler-page-renderer.h>
#include <poppler/cpp/poppler-page.h>

#include <cmath>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/read_image.h"

namespace chromatag {
namespace {

// Copies a 32-bit 0xAARRGGBB (or xRGB) raster into a BGR Mat.
cv::Mat FromXrgb(const unsigned char* data, int width, int height, int stride) {
  cv::Mat bgra(height, width, CV_8UC4, const_cast<unsigned char*>(data), stride);
  cv::Mat bgr;
  cv::cvtColor(bgra, bgr, cv::COLOR_BGRA2BGR);
  return bgr;
}

bool RasterizePdf(const std::string& path, double dpi, std::vector<cv::Mat>* pages,
                  std::string* error) {
  std::unique_ptr<poppler::document> document(poppler::document::load_from_file(path));
  if (!document) {
    *error = "cannot read PDF '" + path + "'";
    return false;
  }
  poppler::page_renderer renderer;
  renderer.set_render_hint(poppler::page_renderer::antialiasing, true);
  for (int i = 0; i < document->pages(); ++i) {
    std::unique_ptr<poppler::page> page(document->create_page(i));
    const poppler::image image =
        page ? renderer.render_page(page.get(), dpi, dpi) : poppler::image();
    if (!image.is_valid()) {
      *error = "cannot render page " + std::to_string(i + 1) + " of '" + path + "'";
      return false;
    }
    pages->push_back(FromXrgb(reinterpret_cast<const unsigned char*>(image.const_data()),
                              image.width(), image.height(), image.bytes_per_row()));
  }
  return true;
}

bool RasterizeSvg(const std::string& path, double dpi, std::vector<cv::Mat>* pages,
                  std::string* error) {
  GError* gerror = nullptr;
  RsvgHandle* handle = rsvg_handle_new_from_file(path.c_str(), &gerror);
  if (handle == nullptr) {
    *error = "cannot read SVG '" + path + "': " + (gerror ? gerror->message : "unknown error");
    if (gerror) g_error_free(gerror);
    return false;
  }
  rsvg_handle_set_dpi(handle, dpi);
  double width = 0.0, height = 0.0;
  if (!rsvg_handle_get_intrinsic_size_in_pixels(handle, &width, &height)) {
    *error = "SVG '" + path + "' has no physical size";
    g_object_unref(handle);
    return false;
  }
  const int w = static_cast<int>(std::lround(width));
  const int h = static_cast<int>(std::lround(height));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  const RsvgRectangle viewport{0.0, 0.0, width, height};
  const bool ok = rsvg_handle_render_document(handle, cr, &viewport, &gerror);
  cairo_destroy(cr);
  g_object_unref(handle);
  if (!ok) {
    *error = "cannot render SVG '" + path + "': " + (gerror ? gerror->message : "unknown error");
    if (gerror) g_error_free(gerror);
    cairo_surface_destroy(surface);
    return false;
  }
  cairo_surface_flush(surface);
  pages->push_back(FromXrgb(cairo_image_surface_get_data(surface), w, h,
                            cairo_image_surface_get_stride(surface)));
  cairo_surface_destroy(surface);
  return true;
}

}  // namespace

cv::Point2d MmToPixel(const std::array<double, 2>& mm, double px_per_mm) {
  return {mm[0] * px_per_mm - 0.5, mm[1] * px_per_mm - 0.5};
}

std::array<double, 2> PixelToMm(const cv::Point2d& px, double px_per_mm) {
  return {(px.x + 0.5) / px_per_mm, (px.y + 0.5) / px_per_mm};
}

std::optional<SheetImages> RasterizeSheet(const SheetRecord& record, double dpi,
                                          std::string* error) {
  std::string message;
  SheetImages images;
  images.px_per_mm = dpi / 25.4;
  bool ok = true;
  switch (record.format) {
    case SheetFormat::kPdf:
      ok = RasterizePdf(record.files.at(0).path, dpi, &images.pages, &message);
      break;
    case SheetFormat::kSvg:
      for (size_t i = 0; ok && i < record.files.size(); ++i) {
        ok = RasterizeSvg(record.files[i].path, dpi, &images.pages, &message);
      }
      break;
    case SheetFormat::kPng:
      images.px_per_mm = record.dpi / 25.4;
      for (size_t i = 0; ok && i < record.files.size(); ++i) {
        cv::Mat page = ReadImage(record.files[i].path, &message);
        ok = !page.empty();
        images.pages.push_back(page);
      }
      break;
  }
  if (ok && static_cast<int>(images.pages.size()) != record.num_pages) {
    message = "the sheet has " + std::to_string(images.pages.size()) +
              " page(s) but its sidecar describes " + std::to_string(record.num_pages);
    ok = false;
  }
  if (!ok) {
    if (error) *error = message;
    return std::nullopt;
  }
  return images;
}

}  // namespace chromatag
