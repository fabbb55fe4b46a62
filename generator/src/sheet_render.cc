// Rendering a laid-out sheet with Cairo and writing it with its sidecar.
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "chromatag/families/version.h"
#include "chromatag/generator/cairo_util.h"
#include "chromatag/generator/id_list.h"
#include "chromatag/generator/sheet.h"
#include "sheet_internal.h"

namespace chromatag {
namespace {

using internal::Mm;

constexpr double kPointsPerMm = 72.0 / 25.4;
void DrawCropMarks(cairo_t* cr, double x0, double y0, double side) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 0.15);
  const double gap = internal::kCropMarkGapMm;
  const double reach = internal::kCropMarkReachMm;
  for (double cx : {x0, x0 + side}) {
    for (double cy : {y0, y0 + side}) {
      const double sx = cx == x0 ? -1.0 : 1.0;
      const double sy = cy == y0 ? -1.0 : 1.0;
      cairo_move_to(cr, cx + sx * gap, cy);
      cairo_line_to(cr, cx + sx * reach, cy);
      cairo_move_to(cr, cx, cy + sy * gap);
      cairo_line_to(cr, cx, cy + sy * reach);
    }
  }
  cairo_stroke(cr);
}

// A bar of alternating 10 mm black and white blocks with a one-line note.
void DrawScaleBar(cairo_t* cr, const SheetOptions& options, const SheetLayout& layout, int page) {
  const double x = options.margin_mm;
  const double y = options.page.height_mm - options.margin_mm - 4.0;
  const double length = layout.scale_bar_mm;
  const double block = length >= 50.0 ? 10.0 : length / 5.0;
  cairo_set_source_rgb(cr, 0, 0, 0);
  for (int i = 0; i * block < length - 1e-9; i += 2)
    cairo_rectangle(cr, x + i * block, y, block, 2.5);
  cairo_fill(cr);
  cairo_set_line_width(cr, 0.2);
  cairo_rectangle(cr, x, y, length, 2.5);
  cairo_stroke(cr);
  // Two lines, so that narrow pages keep both whole.
  const std::string mm = Mm(length).substr(0, Mm(length).size() - 2);
  DrawText(cr, x, y - 1.2, 2.4,
           "This bar is " + mm + " mm long; if not, print at 100 % (no fit to page).");
  if (options.board) {
    const int first = options.ids.front();
    DrawText(cr, x, y - 4.4, 2.4,
             "ChromaTag " + options.family->name() + " board " +
                 std::to_string(options.board->columns) + " x " +
                 std::to_string(options.board->rows) + " (ID " + std::to_string(first) +
                 " top left), palette " + options.palette.name + ", tag size " +
                 Mm(options.tag_size_mm) + " mm, spacing " + Mm(options.board->spacing_mm) + " mm");
  } else {
    DrawText(cr, x, y - 4.4, 2.4,
             "ChromaTag " + options.family->name() + ", palette " + options.palette.name +
                 ", tag size " + Mm(options.tag_size_mm) + " mm, page " + std::to_string(page + 1) +
                 " of " + std::to_string(layout.num_pages));
  }
}

// A board's axes, in the band left of and below its quiet zone: x along the
// bottom and y up the left side, each starting level with the origin (the
// bottom-left corner of the bottom-left black square) at a tick.
void DrawBoardAxes(cairo_t* cr, const SheetOptions& options, const SheetLayout& layout) {
  const double ox = layout.board_origin_mm[0], oy = layout.board_origin_mm[1];
  const double off = internal::QuietZoneMm(options) + 3.0;
  const double length = std::fmax(10.0, std::fmin(options.tag_size_mm, 40.0));
  const double head = 1.8, tick = 1.2;
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, 0.3);
  const double bx = ox - off, by = oy + off;  // Where the two arrows' lines would meet.
  // x: a tick under the origin, the shaft, the head.
  cairo_move_to(cr, ox, by - tick);
  cairo_line_to(cr, ox, by + tick);
  cairo_move_to(cr, ox, by);
  cairo_line_to(cr, ox + length, by);
  cairo_stroke(cr);
  cairo_move_to(cr, ox + length + head, by);
  cairo_line_to(cr, ox + length, by - head / 2);
  cairo_line_to(cr, ox + length, by + head / 2);
  cairo_close_path(cr);
  cairo_fill(cr);
  // y: a tick beside the origin, the shaft, the head.
  cairo_move_to(cr, bx - tick, oy);
  cairo_line_to(cr, bx + tick, oy);
  cairo_move_to(cr, bx, oy);
  cairo_line_to(cr, bx, oy - length);
  cairo_stroke(cr);
  cairo_move_to(cr, bx, oy - length - head);
  cairo_line_to(cr, bx - head / 2, oy - length);
  cairo_line_to(cr, bx + head / 2, oy - length);
  cairo_close_path(cr);
  cairo_fill(cr);
  DrawText(cr, ox + length + head + 0.8, by + 1.0, 3.0, "x");
  DrawText(cr, bx - 1.0, oy - length - head - 0.8, 3.0, "y");
  DrawText(cr, bx - 1.5, by + 4.0, 2.2, "origin at the ticks; z out of the page");
}

void DrawPage(cairo_t* cr, const SheetOptions& options, const SheetLayout& layout,
              const TagColors& colors, int page) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  const double outer = internal::OuterMm(options);
  const double pad = (outer - options.tag_size_mm) / 2.0;
  for (const PlacedTag& tag : layout.tags) {
    if (tag.page != page) continue;
    const double x = tag.corners_mm[0][0];
    const double y = tag.corners_mm[0][1];
    DrawTag(cr, *options.family, tag.id, colors, x, y, options.tag_size_mm, options.tag);
    if (options.crop_marks) DrawCropMarks(cr, x - pad, y - pad, outer);
    if (options.label && !options.board) {
      const double font = internal::LabelFontMm(options);
      cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
      DrawText(cr, x - pad, y - pad + outer + internal::MarksMm(options) + font * 1.1, font,
               options.family->name() + "  ID " + std::to_string(tag.id) + "  " +
                   Mm(options.tag_size_mm) + " mm");
    }
  }
  if (options.board) DrawBoardAxes(cr, options, layout);
  DrawScaleBar(cr, options, layout, page);
}

std::string Metadata(const SheetOptions& options, const std::string& what) {
  if (what == "title") {
    std::vector<int> sorted = options.ids;
    std::sort(sorted.begin(), sorted.end());
    return "ChromaTag " + options.family->name() + " IDs " + FormatIdRanges(sorted);
  }
  if (what == "subject") {
    return "family " + options.family->name() + "; palette " + options.palette.name +
           "; tag size (black square) " + Mm(options.tag_size_mm) + " mm" +
           (options.color_lut ? "; colour LUT applied" : "");
  }
  std::string keywords = "palette " + options.palette.name + " CIELAB D65:";
  for (Shade shade : kAllShades) {
    const Lab& lab = options.palette[shade];
    char entry[96];
    std::snprintf(entry, sizeof(entry), " %s %.2f/%.2f/%.2f %s;", ShadeName(shade), lab.L, lab.a,
                  lab.b, ToHex(options.palette.Srgb8(shade)).c_str());
    keywords += entry;
  }
  return keywords;
}

std::string RenderPdf(const SheetOptions& options, const SheetLayout& layout,
                      const TagColors& colors) {
  std::string bytes;
  cairo_surface_t* surface = cairo_pdf_surface_create_for_stream(
      AppendToString, &bytes, options.page.width_mm * kPointsPerMm,
      options.page.height_mm * kPointsPerMm);
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE,
                                 Metadata(options, "title").c_str());
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_SUBJECT,
                                 Metadata(options, "subject").c_str());
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_KEYWORDS,
                                 Metadata(options, "keywords").c_str());
  const std::string creator = std::string("chromatag ") + kVersion;
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, creator.c_str());
  // No creation date: identical inputs give byte-identical files.
  cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATE_DATE, "");
  cairo_t* cr = cairo_create(surface);
  cairo_scale(cr, kPointsPerMm, kPointsPerMm);
  for (int page = 0; page < layout.num_pages; ++page) {
    DrawPage(cr, options, layout, colors, page);
    cairo_show_page(cr);
  }
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  cairo_surface_destroy(surface);
  return bytes;
}

std::string RenderSvgPage(const SheetOptions& options, const SheetLayout& layout,
                          const TagColors& colors, int page) {
  std::string bytes;
  cairo_surface_t* surface = cairo_svg_surface_create_for_stream(
      AppendToString, &bytes, options.page.width_mm * kPointsPerMm,
      options.page.height_mm * kPointsPerMm);
  cairo_svg_surface_restrict_to_version(surface, CAIRO_SVG_VERSION_1_1);
  cairo_svg_surface_set_document_unit(surface, CAIRO_SVG_UNIT_PT);
  cairo_t* cr = cairo_create(surface);
  cairo_scale(cr, kPointsPerMm, kPointsPerMm);
  DrawPage(cr, options, layout, colors, page);
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  cairo_surface_destroy(surface);
  return bytes;
}

std::string RenderPngPage(const SheetOptions& options, const SheetLayout& layout,
                          const TagColors& colors, int page) {
  const double px_per_mm = options.dpi / 25.4;
  const int width = static_cast<int>(std::lround(options.page.width_mm * px_per_mm));
  const int height = static_cast<int>(std::lround(options.page.height_mm * px_per_mm));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cairo_t* cr = cairo_create(surface);
  cairo_scale(cr, px_per_mm, px_per_mm);
  DrawPage(cr, options, layout, colors, page);
  cairo_destroy(cr);
  const std::string bytes = EncodePng(surface, options.dpi);
  cairo_surface_destroy(surface);
  return bytes;
}

std::string Stem(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const auto dot = path.find_last_of('.');
  return dot == std::string::npos || (slash != std::string::npos && dot < slash)
             ? path
             : path.substr(0, dot);
}

std::string Extension(const std::string& path) {
  const std::string stem = Stem(path);
  return path.substr(stem.size());
}

}  // namespace

TagColors SheetColors(const SheetOptions& options) {
  TagColors colors = TagColors::FromPalette(options.palette);
  if (options.color_lut) {
    for (Shade shade : kAllShades) {
      colors[shade] = ToRgb(ToRgb8(options.color_lut->Apply(colors[shade])));
    }
  }
  return colors;
}

std::optional<SheetFormat> FormatFromPath(const std::string& path, std::string* error) {
  std::string extension = Extension(path);
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (extension == ".pdf") return SheetFormat::kPdf;
  if (extension == ".svg") return SheetFormat::kSvg;
  if (extension == ".png") return SheetFormat::kPng;
  if (error) {
    *error =
        "cannot tell the format of '" + path + "' (use .pdf, .svg or .png, or give the format)";
  }
  return std::nullopt;
}

std::optional<std::vector<OutputFile>> RenderSheet(const SheetOptions& options,
                                                   const std::string& output_path,
                                                   std::string* error) {
  const auto layout = LayoutSheet(options, error);
  if (!layout) return std::nullopt;
  const TagColors colors = SheetColors(options);
  std::vector<OutputFile> files;
  if (options.format == SheetFormat::kPdf) {
    files.push_back({output_path, RenderPdf(options, *layout, colors)});
  } else {
    for (int page = 0; page < layout->num_pages; ++page) {
      const std::string path =
          page == 0 ? output_path
                    : Stem(output_path) + "-" + std::to_string(page + 1) + Extension(output_path);
      files.push_back({path, options.format == SheetFormat::kSvg
                                 ? RenderSvgPage(options, *layout, colors, page)
                                 : RenderPngPage(options, *layout, colors, page)});
      if (files.back().contents.empty()) {
        // Cairo could not hold the page (memory): refused, not written empty.
        if (error) *error = "cannot render page " + std::to_string(page + 1) + " of '" + path + "'";
        return std::nullopt;
      }
    }
  }
  files.push_back(
      {SidecarPath(output_path), SidecarJson(internal::SheetRecordOf(options, *layout, files))});
  return files;
}

bool WriteSheet(const SheetOptions& options, const std::string& output_path, std::string* error,
                std::vector<std::string>* written) {
  const auto files = RenderSheet(options, output_path, error);
  if (!files || !WriteFilesAtomically(*files, error)) return false;
  if (written) {
    written->clear();
    for (const auto& file : *files) written->push_back(file.path);
  }
  return true;
}

}  // namespace chromatag
