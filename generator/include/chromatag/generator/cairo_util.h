// Small Cairo helpers shared by everything the project draws: sheets,
// calibration sheets and reports.
#ifndef CHROMATAG_GENERATOR_CAIRO_UTIL_H_
#define CHROMATAG_GENERATOR_CAIRO_UTIL_H_

#include <cairo.h>

#include <functional>
#include <string>

namespace chromatag {

// The largest side of a Cairo image surface, in pixels.
inline constexpr double kMaxRasterSidePx = 32767.0;

// Why a page of width_mm x height_mm cannot be drawn as an image at `dpi`:
// over Cairo's side limit or over kMaxImagePixels, the budget every reader
// of the project holds to (so a PNG written can be read back). The message
// gives the size it would take and the highest dpi that fits. "" when it
// fits.
std::string RasterPageProblem(double width_mm, double height_mm, double dpi);

// The font of every label and note (Debian's fonts-dejavu-core).
inline constexpr const char* kLabelFont = "DejaVu Sans";

// Draws `text` with its baseline starting at (x, y), `size` user units high,
// in the current source colour.
void DrawText(cairo_t* cr, double x, double y, double size, const std::string& text,
              bool bold = false);

// A cairo_write_func_t that appends to the std::string passed as `closure`,
// for rendering PDF, SVG and PNG into memory.
cairo_status_t AppendToString(void* closure, const unsigned char* data, unsigned int length);

// Encodes an image surface as PNG with its resolution recorded (a pHYs chunk,
// which Cairo does not write), so that it prints at the intended size.
std::string EncodePng(cairo_surface_t* surface, double dpi);

// A document of `pages` pages of width x height points drawn into a PDF in
// memory: `draw(cr, page)` draws each page (from 0) and the page is shown
// after it. The title goes into the metadata; no creation date, so that
// identical drawings give byte-identical files.
std::string RenderPdf(double width, double height, const std::string& title, int pages,
                      const std::function<void(cairo_t*, int)>& draw);

// An image of width x height pixels (RGB, black until drawn) drawn by
// `draw` and encoded as PNG, with its resolution recorded when dpi > 0.
// "" when Cairo cannot make a surface of that size.
std::string RenderPng(int width, int height, double dpi, const std::function<void(cairo_t*)>& draw);

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_CAIRO_UTIL_H_
