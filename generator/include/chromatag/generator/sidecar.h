// Reading the sidecar JSON that WriteSheet puts beside every sheet
// (docs/generator.md, "Sidecar"), for the verify and calibration tools.
#ifndef CHROMATAG_GENERATOR_SIDECAR_H_
#define CHROMATAG_GENERATOR_SIDECAR_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/sheet.h"

namespace chromatag {

struct SheetRecord {
  std::string sidecar_path;
  std::shared_ptr<const TagFamily> family;
  double tag_size_mm = 0.0;
  int quiet_zone_cells = 0;
  Palette palette;
  PageSize page;
  int num_pages = 0;
  SheetFormat format = SheetFormat::kPdf;
  double dpi = 0.0;  // PNG only.
  struct File {
    std::string path;  // Resolved against the sidecar's folder.
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

// Reads and checks a sidecar: schema and version, a known family, kept IDs,
// pages in range, four corners per tag. Refuses (nullopt, *error) anything
// else, naming the path and what is wrong.
std::optional<SheetRecord> ReadSidecar(const std::string& path, std::string* error = nullptr);

// The same from the sidecar's text; `folder` ("dir/" or "") is where its
// files are.
std::optional<SheetRecord> ParseSidecar(const std::string& text, const std::string& folder,
                                        std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_SIDECAR_H_
