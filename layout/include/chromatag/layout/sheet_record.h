// What a generated sheet holds, as its sidecar JSON records it
// (docs/generator.md, "Sidecar"): the family, size and palette of its tags,
// the page, the files written and where each tag lies on its page. The
// generator writes it; the verify and calibration tools and the board
// reader read it back. Page coordinates are millimetres from the page's
// top-left corner, y down.
#ifndef CHROMATAG_LAYOUT_SHEET_RECORD_H_
#define CHROMATAG_LAYOUT_SHEET_RECORD_H_

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "chromatag/base/units.h"
#include "chromatag/families/color.h"
#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"

namespace chromatag {

enum class SheetFormat { kPdf, kSvg, kPng };
const char* SheetFormatName(SheetFormat format);  // "pdf", "svg", "png".
// The format a name gives ("pdf", "svg", "png", lower case); nullopt for any other.
std::optional<SheetFormat> SheetFormatFromName(const std::string& name);

// A board, as Kalibr's AprilGrid and ArUco's GridBoard: `columns` x `rows`
// tags on one page in reading order (the first ID top-left), neighbouring
// black squares `spacing_mm` apart, the board's origin and axes marked on
// the print, and the board frame recorded in the sidecar (docs/pose.md).
struct BoardGrid {
  int columns = 0;
  int rows = 0;
  double spacing_mm = 10.0;  // Between neighbouring black squares; >= the quiet zone.
};

struct PlacedTag {
  int id = 0;
  int page = 0;  // From 0.
  // Black square's corners in the order of spec section 7: top-left,
  // top-right, bottom-right, bottom-left of the upright tag.
  std::array<std::array<double, 2>, 4> corners_mm;
  std::array<double, 2> center_mm;
};

struct SheetRecord {
  std::string sidecar_path;  // Set by ReadSidecar.
  std::shared_ptr<const TagFamily> family;
  double tag_size_mm = 0.0;
  int quiet_zone_cells = 0;
  Palette palette;
  PageSize page;
  int num_pages = 0;
  SheetFormat format = SheetFormat::kPdf;
  double dpi = 0.0;  // PNG only.
  // How the sheet was drawn: recorded for the reader of the file; the tools
  // that read a sidecar back do not need them and leave the defaults.
  double margin_mm = 0.0;
  bool cut_ring = false;
  bool crop_marks = false;
  bool label = false;
  std::array<Rgb8, kNumShades> written_rgb{};  // Each shade as sent to the printer.
  std::string color_lut;                       // The LUT's file name; "" for none.
  struct File {
    // Written: the file's name beside the sidecar. Read: resolved against
    // the sidecar's folder.
    std::string path;
    std::string sha256;
  };
  std::vector<File> files;  // One PDF, or one SVG or PNG per page.
  std::vector<PlacedTag> tags;
  // Sheets written as a board: the grid, and the board frame's origin in
  // page coordinates (mm from the top-left, y down). Other sheets have none;
  // as boards, their origin is the page's bottom-left corner.
  std::optional<BoardGrid> board;
  std::array<double, 2> board_origin_mm{0.0, 0.0};
};

// The sidecar path for an output path: "tags.pdf" -> "tags.pdf.json". One
// sidecar per output, so that tags.pdf and tags.svg written one after the
// other each keep their own (a shared tags.json let verify trust the wrong one).
std::string SidecarPath(const std::string& output_path);

// The sidecar's text for `record` (files named by their base names).
std::string SidecarJson(const SheetRecord& record);

// Reads and checks a sidecar: schema and version, a known family, kept IDs,
// pages in range, four corners per tag. Refuses (nullopt, *error) anything
// else, naming the path and what is wrong.
std::optional<SheetRecord> ReadSidecar(const std::string& path, std::string* error = nullptr);
// The same from the sidecar's text; `folder` ("dir/" or "") is where its
// files are.
std::optional<SheetRecord> ParseSidecar(const std::string& text, const std::string& folder,
                                        std::string* error = nullptr);

// The text of the sidecar beside a sheet file (`sheet_path` + ".json", into
// *sidecar_path), once it is known to describe that file: its "files" list
// names the sheet and records the sheet's SHA-256. Any sheet the toolkit
// writes (tag sheets, colour calibration sheets) has one. `kind` names the
// sheet in errors.
std::optional<std::string> ReadSidecarOfSheet(const std::string& sheet_path,
                                              const std::string& kind, std::string* sidecar_path,
                                              std::string* error);

}  // namespace chromatag

#endif  // CHROMATAG_LAYOUT_SHEET_RECORD_H_
