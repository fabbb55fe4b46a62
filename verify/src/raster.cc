#include "chromatag/verify/raster.h"

#include <librsvg/rsvg.h>
#include <poppler/cpp/poppler-document.h>
#include <poppler/cpp/poppler-page-renderer.h>
#include <poppler/cpp/poppler-page.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "chromatag/base/input_file.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/generator/cairo_util.h"
#include "poppler_messages.h"

namespace chromatag {

struct SheetPages::Source {
  SheetFormat format = SheetFormat::kPdf;
  std::vector<std::string> paths;  // The PDF, or one file per page.
  std::unique_ptr<poppler::document> pdf;
  double dpi = 0.0;
};

namespace {

// Copies a 32-bit 0xAARRGGBB (or xRGB) raster into a BGR Mat.
cv::Mat FromXrgb(const unsigned char* data, int width, int height, int stride) {
  cv::Mat bgra(height, width, CV_8UC4, const_cast<unsigned char*>(data), stride);
  cv::Mat bgr;
  cv::cvtColor(bgra, bgr, cv::COLOR_BGRA2BGR);
  return bgr;
}

// Why page `index` cannot be drawn at `dpi`, or "".
std::string PageSizeProblem(int index, double width_mm, double height_mm, double dpi) {
  const std::string problem = RasterPageProblem(width_mm, height_mm, dpi);
  return problem.empty() ? "" : "page " + std::to_string(index + 1) + ": " + problem;
}

// Loads an SVG with librsvg at `dpi`; nullptr and *error when it cannot.
RsvgHandle* LoadSvg(const std::string& path, double dpi, double* width, double* height,
                    std::string* error) {
  GError* gerror = nullptr;
  RsvgHandle* handle = rsvg_handle_new_from_file(path.c_str(), &gerror);
  if (handle == nullptr) {
    *error = "cannot read SVG '" + path + "': " + (gerror ? gerror->message : "unknown error");
    if (gerror) g_error_free(gerror);
    return nullptr;
  }
  rsvg_handle_set_dpi(handle, dpi);
  if (!rsvg_handle_get_intrinsic_size_in_pixels(handle, width, height) ||
      !(*width >= 1.0 && *height >= 1.0)) {
    *error = "SVG '" + path + "' has no physical size";
    g_object_unref(handle);
    return nullptr;
  }
  return handle;
}

cv::Mat RenderSvg(const std::string& path, double dpi, std::string* error) {
  double width = 0.0, height = 0.0;
  RsvgHandle* handle = LoadSvg(path, dpi, &width, &height, error);
  if (handle == nullptr) return {};
  const int w = static_cast<int>(std::lround(width));
  const int h = static_cast<int>(std::lround(height));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    *error = "cannot render SVG '" + path +
             "': " + cairo_status_to_string(cairo_surface_status(surface));
    cairo_surface_destroy(surface);
    g_object_unref(handle);
    return {};
  }
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  const RsvgRectangle viewport{0.0, 0.0, width, height};
  GError* gerror = nullptr;
  const bool ok = rsvg_handle_render_document(handle, cr, &viewport, &gerror);
  cairo_destroy(cr);
  g_object_unref(handle);
  cv::Mat page;
  if (ok) {
    cairo_surface_flush(surface);
    page = FromXrgb(cairo_image_surface_get_data(surface), w, h,
                    cairo_image_surface_get_stride(surface));
  } else {
    *error = "cannot render SVG '" + path + "': " + (gerror ? gerror->message : "unknown error");
    if (gerror) g_error_free(gerror);
  }
  cairo_surface_destroy(surface);
  return page;
}

std::string CountProblem(int found, int described) {
  return "the sheet has " + std::to_string(found) + " page(s) but its sidecar describes " +
         std::to_string(described);
}

}  // namespace

namespace {

// Each page's size in pixels at `dpi`, as poppler will draw it; what is
// wrong with the PDF's pages, or empty.
std::string PdfPageSizes(poppler::document& pdf, const std::string& path, int num_pages, double dpi,
                         std::vector<cv::Size>* sizes) {
  const int count = pdf.pages();
  if (count != num_pages) return CountProblem(count, num_pages);
  for (int i = 0; i < count; ++i) {
    std::unique_ptr<poppler::page> page(pdf.create_page(i));
    if (!page) return "cannot read page " + std::to_string(i + 1) + " of '" + path + "'";
    const poppler::rectf box = page->page_rect();
    const double w_mm = box.width() / 72.0 * 25.4, h_mm = box.height() / 72.0 * 25.4;
    const std::string problem = PageSizeProblem(i, w_mm, h_mm, dpi);
    if (!problem.empty()) return problem;
    // As poppler draws it: rounded, and turned by the page's /Rotate.
    const int w = static_cast<int>(std::floor(w_mm / 25.4 * dpi + 0.5));
    const int h = static_cast<int>(std::floor(h_mm / 25.4 * dpi + 0.5));
    const bool turned = page->orientation() == poppler::page::landscape ||
                        page->orientation() == poppler::page::seascape;
    sizes->emplace_back(turned ? h : w, turned ? w : h);
  }
  return "";
}

// Each page file's size in pixels (an SVG's at `dpi`, a PNG's its own);
// what is wrong with them, or empty.
std::string PageFileSizes(const std::vector<std::string>& paths, SheetFormat format, int num_pages,
                          double dpi, std::vector<cv::Size>* sizes) {
  if (static_cast<int>(paths.size()) != num_pages)
    return CountProblem(static_cast<int>(paths.size()), num_pages);
  std::string message;
  for (size_t i = 0; i < paths.size(); ++i) {
    const std::string& path = paths[i];
    if (format == SheetFormat::kSvg) {
      double w = 0.0, h = 0.0;
      RsvgHandle* handle = LoadSvg(path, dpi, &w, &h, &message);
      if (handle == nullptr) return message;
      g_object_unref(handle);
      const std::string problem =
          PageSizeProblem(static_cast<int>(i), w / dpi * 25.4, h / dpi * 25.4, dpi);
      if (!problem.empty()) return problem;
      sizes->emplace_back(static_cast<int>(std::lround(w)), static_cast<int>(std::lround(h)));
    } else {
      ImageSize size;
      if (!ImageHeaderSize(path, &size)) return "cannot read the size of PNG page '" + path + "'";
      const std::string problem = ImageSizeProblem(size);
      if (!problem.empty()) return "PNG page '" + path + "': " + problem;
      sizes->emplace_back(static_cast<int>(size.width), static_cast<int>(size.height));
    }
  }
  return "";
}

}  // namespace

std::optional<SheetPages> SheetPages::Open(const SheetRecord& record, double dpi,
                                           std::string* error) {
  auto source = std::make_shared<Source>();
  source->format = record.format;
  source->dpi = dpi;
  for (const auto& file : record.files) source->paths.push_back(file.path);
  SheetPages pages;
  pages.px_per_mm_ = (record.format == SheetFormat::kPng ? record.dpi : dpi) / 25.4;
  const auto fail = [&](const std::string& why) -> std::optional<SheetPages> {
    if (error) *error = why;
    return std::nullopt;
  };
  if (source->paths.empty()) return fail("the sidecar lists no sheet file");
  std::string problem;
  if (record.format == SheetFormat::kPdf) {
    PopplerMessages messages;
    source->pdf.reset(poppler::document::load_from_file(source->paths[0]));
    if (!source->pdf || source->pdf->is_locked())
      return fail("cannot read PDF '" + source->paths[0] + "'" + messages.Note());
    problem = PdfPageSizes(*source->pdf, source->paths[0], record.num_pages, dpi, &pages.sizes_);
  } else {
    problem = PageFileSizes(source->paths, record.format, record.num_pages, dpi, &pages.sizes_);
  }
  if (!problem.empty()) return fail(problem);
  pages.source_ = std::move(source);
  return pages;
}

cv::Mat SheetPages::Render(int index, std::string* error) const {
  std::string message;
  cv::Mat page;
  if (index < 0 || index >= size()) {
    message =
        "no page " + std::to_string(index + 1) + " (the sheet has " + std::to_string(size()) + ")";
  } else if (source_->format == SheetFormat::kPdf) {
    PopplerMessages messages;
    std::unique_ptr<poppler::page> pdf_page(source_->pdf->create_page(index));
    poppler::page_renderer renderer;
    renderer.set_render_hint(poppler::page_renderer::antialiasing, true);
    const poppler::image image =
        pdf_page ? renderer.render_page(pdf_page.get(), source_->dpi, source_->dpi)
                 : poppler::image();
    if (image.is_valid()) {
      page = FromXrgb(reinterpret_cast<const unsigned char*>(image.const_data()), image.width(),
                      image.height(), image.bytes_per_row());
    } else {
      message = "cannot render page " + std::to_string(index + 1) + " of '" + source_->paths[0] +
                "'" + messages.Note();
    }
  } else if (source_->format == SheetFormat::kSvg) {
    page = RenderSvg(source_->paths[index], source_->dpi, &message);
  } else {
    page = ReadImage(source_->paths[index], &message);
  }
  if (page.empty() && error) *error = message;
  return page;
}

std::optional<SheetImages> RasterizeSheet(const SheetRecord& record, double dpi,
                                          std::string* error) {
  auto pages = SheetPages::Open(record, dpi, error);
  if (!pages) return std::nullopt;
  SheetImages images;
  images.px_per_mm = pages->px_per_mm();
  for (int i = 0; i < pages->size(); ++i) {
    images.pages.push_back(pages->Render(i, error));
    if (images.pages.back().empty()) return std::nullopt;
  }
  return images;
}

cv::Point2d MmToPixel(const std::array<double, 2>& mm, double px_per_mm) {
  return {mm[0] * px_per_mm - 0.5, mm[1] * px_per_mm - 0.5};
}

std::array<double, 2> PixelToMm(const cv::Point2d& px, double px_per_mm) {
  return {(px.x + 0.5) / px_per_mm, (px.y + 0.5) / px_per_mm};
}

}  // namespace chromatag
