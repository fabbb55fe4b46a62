#include "chromatag/generator/sheet_request.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "chromatag/base/input_file.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/id_list.h"
#include "sheet_internal.h"

namespace chromatag {
namespace {

// A board's spacing when none is given, as a share of the tag size (Kalibr's
// AprilGrids are commonly printed at 0.3).
constexpr double kDefaultBoardSpacingShare = 0.25;

// "6x4" as a grid of 1 to 100 columns and rows; none for a sheet (no --board).
bool ParseBoard(const SheetRequest& in, std::optional<BoardGrid>* board, std::string* error) {
  if (in.board.empty()) {
    if (in.spacing.empty()) return true;
    *error = "a spacing is for boards (COLSxROWS tags); sheets take a gap";
    return false;
  }
  BoardGrid grid;
  const std::string& text = in.board;
  const auto x = text.find_first_of("xX");
  const auto whole = [](const std::string& digits, int* value) {
    const auto end = digits.data() + digits.size();
    const auto [at, ec] = std::from_chars(digits.data(), end, *value);
    return !digits.empty() && ec == std::errc() && at == end;
  };
  if (x == std::string::npos || !whole(text.substr(0, x), &grid.columns) ||
      !whole(text.substr(x + 1), &grid.rows) || grid.columns < 1 || grid.rows < 1 ||
      grid.columns > 100 || grid.rows > 100) {
    *error = "the board must be COLSxROWS with 1 to 100 of each, e.g. 6x4, not '" + in.board + "'";
    return false;
  }
  *board = grid;
  return true;
}

// The IDs asked for; a board without them takes the family's first kept ones.
bool ChooseIds(const SheetRequest& in, const std::optional<BoardGrid>& board, SheetOptions* out,
               std::string* error) {
  if (board && !in.all && in.ids.empty()) {
    const size_t board_tags =
        static_cast<size_t>(board->columns) * static_cast<size_t>(board->rows);
    const std::vector<int>& kept = out->family->kept_ids();
    if (kept.size() < board_tags) {
      *error = "a " + in.board + " board needs " + std::to_string(board_tags) + " tags; " +
               out->family->name() + " keeps " + std::to_string(kept.size()) + " IDs" +
               (out->family->name() == "16h5" ? " (36h11 keeps more)" : "");
      return false;
    }
    out->ids.assign(kept.begin(), kept.begin() + static_cast<std::ptrdiff_t>(board_tags));
  } else if (in.all == !in.ids.empty()) {
    *error = "say which tags: a list of IDs (0-9,12) or all kept IDs (not both)";
    return false;
  } else if (in.all) {
    out->ids = out->family->kept_ids();
  } else {
    auto ids = ParseIdList(in.ids, *out->family, error);
    if (!ids) return false;
    out->ids = *ids;
  }
  return true;
}

// Margin, gap, page size, palette and colour LUT.
bool ReadPageAndColours(const SheetRequest& in, SheetOptions* out, std::string* error) {
  const auto margin = ParseLength(in.margin == "0" ? "0.000001mm" : in.margin, error);
  if (!margin) return false;
  const auto gap = ParseLength(in.gap == "0" ? "0.000001mm" : in.gap, error);
  if (!gap) return false;
  out->margin_mm = margin->mm;
  out->gap_mm = gap->mm;
  const auto page = ParsePageSize(in.page, error);
  if (!page) return false;
  out->page = *page;
  const auto palette = in.palette_file.empty() ? BuiltinPalette(in.palette, error)
                                               : LoadPaletteFile(in.palette_file, error);
  if (!palette) return false;
  out->palette = *palette;
  if (!in.color_lut.empty()) {
    out->color_lut = ColorLut::Load(in.color_lut, error);
    if (!out->color_lut) return false;
  }
  return true;
}

// The page turned, its name saying which way it now stands.
SheetOptions WithPageTurned(const SheetOptions& sheet) {
  SheetOptions turned = sheet;
  std::swap(turned.page.width_mm, turned.page.height_mm);
  turned.page.name += turned.page.width_mm > turned.page.height_mm ? " landscape" : " portrait";
  return turned;
}

// The largest board tags that fit the page, turned if that fits larger ones.
// A given spacing bounds the size too: it must hold a quiet zone.
bool FitBoardTagSize(const SheetRequest& in, double quiet_share,
                     const std::optional<double>& spacing_mm, SheetOptions* out,
                     std::string* error) {
  const double share = std::max(kDefaultBoardSpacingShare, quiet_share);
  const auto fit_on = [&](const SheetOptions& sheet, std::string* why) {
    auto fit = BoardTagSizeToFit(sheet, spacing_mm ? 0.0 : share, why);
    const double largest = spacing_mm ? *spacing_mm / quiet_share : 0.0;
    if (fit && spacing_mm && *fit > largest)
      fit = largest >= 10.0 ? std::floor(largest) : std::floor(largest * 10) / 10;
    return fit;
  };
  if (spacing_mm && *spacing_mm / quiet_share < 1.0) {
    char text[256];
    std::snprintf(text, sizeof(text),
                  "a spacing of %s mm holds the quiet zone of tags of at most %.2f mm (%d cells "
                  "of %d across the black square); tags are 1 mm or more: give a larger spacing "
                  "or a smaller quiet zone",
                  internal::Mm(*spacing_mm).c_str(), *spacing_mm / quiet_share, in.quiet_zone,
                  out->family->black_square_cells());
    *error = text;
    return false;
  }
  auto fit = fit_on(*out, error);
  if (!fit) return false;
  // The page turned, when that fits larger tags (a 6x4 board on A4),
  // unless its orientation was given.
  const SheetOptions turned = WithPageTurned(*out);
  const auto turned_fit = !out->page.may_turn ? std::nullopt : fit_on(turned, nullptr);
  if (turned_fit && *turned_fit > *fit) {
    fit = turned_fit;
    out->page = turned.page;
  }
  out->tag_size_mm = *fit;
  return true;
}

// The tag size and a board's spacing: given, or fitted to the page.
bool ChooseSizeAndSpacing(const SheetRequest& in, const std::optional<BoardGrid>& board,
                          SheetOptions* out, std::string* error) {
  // The quiet zone as a share of the tag size: the least spacing a board's
  // tags may have.
  const double quiet_share = static_cast<double>(in.quiet_zone) / out->family->black_square_cells();
  std::optional<double> spacing_mm;
  if (!in.spacing.empty()) {
    const auto spacing = ParseLength(in.spacing, error);
    if (!spacing) {
      *error = "the spacing: " + *error;
      return false;
    }
    spacing_mm = spacing->mm;
  }
  if (board) {
    out->board = *board;
    if (spacing_mm) out->board->spacing_mm = *spacing_mm;
  }
  if (!in.size.empty()) {
    const auto size = ParseLength(in.size, error);
    if (!size) return false;
    out->tag_size_mm = size->mm;
  } else if (board) {
    if (!FitBoardTagSize(in, quiet_share, spacing_mm, out, error)) return false;
  } else {
    out->tag_size_mm = 40.0;
  }
  if (board && !spacing_mm) {
    // Rounded up to 0.1 mm, and the fitted size lowered when that no longer fits.
    const double share = std::max(kDefaultBoardSpacingShare, quiet_share);
    const double step = out->tag_size_mm >= 10.0 ? 1.0 : 0.1;
    for (int i = 0; i < 3; ++i) {
      out->board->spacing_mm = std::ceil(share * out->tag_size_mm * 10.0 - 1e-9) / 10.0;
      if (!in.size.empty() || LayoutSheet(*out) || out->tag_size_mm - step < 1.0) break;
      out->tag_size_mm -= step;
    }
  }
  return true;
}

// The format given, or else the output's extension; the two must agree.
bool ChooseFormat(const SheetRequest& in, const std::string& output_path, SheetOptions* out,
                  std::string* error) {
  std::string extension_error;
  const auto from_extension = FormatFromPath(output_path, &extension_error);
  if (in.format.empty()) {
    if (!from_extension) {
      *error = extension_error;
      return false;
    }
    out->format = *from_extension;
    return true;
  }
  if (in.format == "pdf") {
    out->format = SheetFormat::kPdf;
  } else if (in.format == "svg") {
    out->format = SheetFormat::kSvg;
  } else if (in.format == "png") {
    out->format = SheetFormat::kPng;
  } else {
    *error = "unknown format '" + in.format + "' (allowed: pdf, svg, png)";
    return false;
  }
  // A PNG named x.pdf opens in no PDF viewer and fools whoever trusts the name.
  if (from_extension && *from_extension != out->format) {
    *error = std::string("the format is ") + SheetFormatName(out->format) + " but '" + output_path +
             "' names a " + SheetFormatName(*from_extension) + " file: give the output a ." +
             SheetFormatName(out->format) + " name or leave the format out";
    return false;
  }
  return true;
}

}  // namespace

bool ToSheetOptions(const SheetRequest& in, const std::string& output_path, SheetOptions* out,
                    std::string* error) {
  if (!IsValidUtf8(output_path)) {
    *error = "the output name must be UTF-8 (the sidecar records it)";
    return false;
  }
  out->family = TagFamily::Load(in.family, error);
  if (!out->family) return false;
  std::optional<BoardGrid> board;
  if (!ParseBoard(in, &board, error) || !ChooseIds(in, board, out, error) ||
      !ReadPageAndColours(in, out, error)) {
    return false;
  }
  out->tag.quiet_zone_cells = in.quiet_zone;
  if (!ChooseSizeAndSpacing(in, board, out, error)) return false;
  out->tag.cut_ring = in.cut_ring;
  out->crop_marks = in.crop_marks;
  out->label = in.label;
  out->one_per_page = in.one_per_page;
  out->dpi = in.dpi;
  if (!ChooseFormat(in, output_path, out, error) || !out->IsValid(error)) return false;
  // A board of a given size that fits only on the page turned gets it turned.
  if (board && !in.size.empty() && out->page.may_turn && !LayoutSheet(*out)) {
    const SheetOptions turned = WithPageTurned(*out);
    if (LayoutSheet(turned)) *out = turned;
  }
  return true;
}

}  // namespace chromatag
