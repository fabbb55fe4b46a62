// Layout and drawing of the calibration sheet (calib_sheet.h).
#include "chromatag/calib/calib_sheet.h"

#include <cairo-pdf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <opencv2/imgproc.hpp>

#include "chromatag/base/sha256.h"
#include "chromatag/families/family.h"
#include "chromatag/families/version.h"
#include "chromatag/generator/cairo_util.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag {
namespace {

constexpr double kHeaderMm = 9.0;  // Title line above the grid.
constexpr double kFooterMm = 6.0;  // Note below the grid.
// White between a corner tag's black square and the nearest patch, in tag
// cells: the detector needs one (spec section 1), 1.5 leaves room for blur.
constexpr double kTagClearanceCells = 1.5;
constexpr double kPointsPerMm = 72.0 / 25.4;

// A deterministic shuffle: std::shuffle's use of the generator is left to the
// standard library, and the order is part of the sheet, so it must not change
// with the compiler.
template <typename T>
void Shuffle(std::vector<T>* items, std::mt19937* rng) {
  for (size_t i = items->size(); i > 1; --i) {
    std::swap((*items)[i - 1], (*items)[(*rng)() % i]);
  }
}

int DerivedSheetId(const CalibSheetOptions& options) {
  char page[64];
  std::snprintf(page, sizeof(page), "%.3fx%.3f", options.page.width_mm, options.page.height_mm);
  const std::string digest = Sha256Hex(PaletteToJson(options.palette) + page);
  return static_cast<int>(std::stoul(digest.substr(0, 8), nullptr, 16) % 65535u) + 1;
}

std::array<int, 4> CornerIds(int sheet_id, const TagFamily& family) {
  std::vector<int> ids = family.kept_ids();
  std::mt19937 rng(static_cast<uint32_t>(sheet_id) * 2654435761u + 17u);
  Shuffle(&ids, &rng);
  return {ids[0], ids[1], ids[2], ids[3]};
}

// Candidates for one colour: a grid over (a*, b*) around the palette's two
// shades, L* interpolated between theirs, kept only inside sRGB.
std::vector<Lab> CandidateColours(const CalibSheetOptions& options, Shade one, Shade zero) {
  const Lab& s1 = options.palette[one];
  const Lab& s0 = options.palette[zero];
  const double a_base = (s1.a + s0.a) / 2.0;
  const double b_lo = std::min(s1.b, s0.b) - options.candidate_b_reach;
  const double b_hi = std::max(s1.b, s0.b) + options.candidate_b_reach;
  std::vector<Lab> out;
  for (double offset : options.candidate_a_offsets) {
    for (int i = 0; i < options.candidate_b_steps; ++i) {
      Lab lab;
      lab.a = a_base + offset;
      lab.b = b_lo + (b_hi - b_lo) * i / (options.candidate_b_steps - 1);
      const double t = std::abs(s1.b - s0.b) > 1e-9 ? (lab.b - s0.b) / (s1.b - s0.b) : 0.5;
      lab.L = s0.L + std::clamp(t, 0.0, 1.0) * (s1.L - s0.L);
      if (!InSrgbGamut(lab, 0.0)) continue;
      const Rgb8 rgb = LabToSrgb8(lab);
      if (rgb == options.palette.Srgb8(one) || rgb == options.palette.Srgb8(zero)) continue;
      out.push_back(lab);
    }
  }
  return out;
}

struct Grid {
  double x0 = 0, y0 = 0, pitch = 0;
  int rows = 0, columns = 0;
  int tag_block = 0;  // Slots per side taken by a corner tag.
};

bool InTagBlock(const Grid& grid, int row, int col) {
  const bool top = row < grid.tag_block, bottom = row >= grid.rows - grid.tag_block;
  const bool left = col < grid.tag_block, right = col >= grid.columns - grid.tag_block;
  return (top || bottom) && (left || right);
}

std::optional<Grid> MakeGrid(const CalibSheetOptions& o, std::string* error) {
  Grid grid;
  grid.pitch = o.patch_mm + o.gap_mm;
  const double width = o.page.width_mm - 2 * o.margin_mm;
  const double height = o.page.height_mm - 2 * o.margin_mm - kHeaderMm - kFooterMm;
  grid.columns = static_cast<int>(std::floor((width + o.gap_mm) / grid.pitch));
  grid.rows = static_cast<int>(std::floor((height + o.gap_mm) / grid.pitch));
  const double cell = o.tag_size_mm / 6.0;  // 16h5: 6 cells across the black square.
  grid.tag_block = 1;
  while ((grid.tag_block * grid.pitch - o.gap_mm - o.tag_size_mm) / 2.0 + o.gap_mm <
         kTagClearanceCells * cell) {
    ++grid.tag_block;
  }
  const int needed = 2 * grid.tag_block + 3;
  if (grid.columns < needed || grid.rows < needed) {
    if (error) {
      char text[320];
      std::snprintf(text, sizeof(text),
                    "page %s (%.1f x %.1f mm) is too small for the calibration sheet: with %.1f mm "
                    "margins, %.1f mm patches and %.1f mm corner tags it needs at least %.1f x "
                    "%.1f mm",
                    o.page.name.c_str(), o.page.width_mm, o.page.height_mm, o.margin_mm, o.patch_mm,
                    o.tag_size_mm, needed * grid.pitch - o.gap_mm + 2 * o.margin_mm,
                    needed * grid.pitch - o.gap_mm + 2 * o.margin_mm + kHeaderMm + kFooterMm);
      *error = text;
    }
    return std::nullopt;
  }
  grid.x0 = o.margin_mm + (width - (grid.columns * grid.pitch - o.gap_mm)) / 2.0;
  grid.y0 = o.margin_mm + kHeaderMm;
  return grid;
}

// Bare-paper slots on a regular lattice, so that the white is known all
// over the sheet (the sampler fits the light's falloff through them).
std::vector<std::pair<int, int>> PaperSlots(const Grid& grid, std::vector<bool>* taken) {
  const int nr = std::max(3, static_cast<int>(std::lround(grid.rows / 3.5)));
  const int nc = std::max(3, static_cast<int>(std::lround(grid.columns / 3.0)));
  std::vector<std::pair<int, int>> slots;
  for (int i = 0; i < nr; ++i) {
    for (int j = 0; j < nc; ++j) {
      const int r0 = static_cast<int>(std::lround((i + 0.5) * grid.rows / nr - 0.5));
      const int c0 = static_cast<int>(std::lround((j + 0.5) * grid.columns / nc - 0.5));
      // The nearest free slot (the lattice point itself unless a tag is there).
      int best = -1;
      double best_d = 1e9;
      for (int r = 0; r < grid.rows; ++r) {
        for (int c = 0; c < grid.columns; ++c) {
          const double d = std::hypot(r - r0, c - c0);
          if (!(*taken)[r * grid.columns + c] && d < best_d) {
            best_d = d;
            best = r * grid.columns + c;
          }
        }
      }
      (*taken)[best] = true;
      slots.push_back({best / grid.columns, best % grid.columns});
    }
  }
  return slots;
}

Patch MakePatch(PatchKind kind, Shade shade, const Lab& lab) {
  Patch patch;
  patch.kind = kind;
  patch.shade = shade;
  patch.lab = lab;
  patch.rgb = LabToSrgb8(lab);
  return patch;
}

// The four corner tags, each centred in its block of grid slots.
std::array<CornerTag, 4> CornerTags(const Grid& grid, const CalibSheetOptions& options,
                                    const std::array<int, 4>& ids) {
  std::array<CornerTag, 4> tags;
  const double block = grid.tag_block * grid.pitch - options.gap_mm;
  const double inset = (block - options.tag_size_mm) / 2.0;
  const double right = grid.x0 + (grid.columns - grid.tag_block) * grid.pitch + inset;
  const double bottom = grid.y0 + (grid.rows - grid.tag_block) * grid.pitch + inset;
  const std::array<std::array<double, 2>, 4> origins = {{{grid.x0 + inset, grid.y0 + inset},
                                                         {right, grid.y0 + inset},
                                                         {right, bottom},
                                                         {grid.x0 + inset, bottom}}};
  for (int k = 0; k < 4; ++k) {
    const double x = origins[k][0], y = origins[k][1], s = options.tag_size_mm;
    tags[k].id = ids[k];
    tags[k].corners_mm = {{{x, y}, {x + s, y}, {x + s, y + s}, {x, y + s}}};
  }
  return tags;
}

// Per slot (row by row): whether a corner tag takes it.
std::vector<bool> TagSlots(const Grid& grid) {
  std::vector<bool> taken(grid.rows * grid.columns, false);
  for (int r = 0; r < grid.rows; ++r) {
    for (int c = 0; c < grid.columns; ++c) taken[r * grid.columns + c] = InTagBlock(grid, r, c);
  }
  return taken;
}

// The slots nothing has taken, row by row.
std::vector<std::pair<int, int>> FreeSlots(const Grid& grid, const std::vector<bool>& taken) {
  std::vector<std::pair<int, int>> free_slots;
  for (int r = 0; r < grid.rows; ++r) {
    for (int c = 0; c < grid.columns; ++c) {
      if (!taken[r * grid.columns + c]) free_slots.push_back({r, c});
    }
  }
  return free_slots;
}

// The coloured patches, one per free slot; refuses (nullopt, *error) when they do not fit.
std::optional<std::vector<Patch>> SlotContents(const CalibSheetOptions& options, size_t free_count,
                                               std::string* error) {
  // What goes into the free slots: the palette's colours, the grey ramp and
  // the candidates; then more palette repeats in what is left.
  const std::array<Shade, 5> shades = {Shade::kRed1, Shade::kRed0, Shade::kGreen1, Shade::kGreen0,
                                       Shade::kBlack};
  std::vector<Patch> contents;
  for (int k = 0; k < options.palette_repeats; ++k) {
    for (Shade shade : shades)
      contents.push_back(MakePatch(PatchKind::kPalette, shade, options.palette[shade]));
  }
  for (int k = 1; k <= options.grey_levels; ++k) {
    const double v = static_cast<double>(k) / (options.grey_levels + 1);
    contents.push_back(MakePatch(PatchKind::kGrey, Shade::kWhite, SrgbToLab(Rgb{v, v, v})));
  }
  std::vector<Patch> candidates;
  for (const Lab& lab : CandidateColours(options, Shade::kRed1, Shade::kRed0))
    candidates.push_back(MakePatch(PatchKind::kCandidate, Shade::kRed1, lab));
  for (const Lab& lab : CandidateColours(options, Shade::kGreen1, Shade::kGreen0))
    candidates.push_back(MakePatch(PatchKind::kCandidate, Shade::kGreen1, lab));
  const size_t room = free_count - std::min(free_count, contents.size());
  if (candidates.size() > room) {
    // Keep an evenly spread subset, so both colours and every a* offset stay.
    std::vector<Patch> kept;
    for (size_t i = 0; i < room; ++i) kept.push_back(candidates[i * candidates.size() / room]);
    candidates = kept;
  }
  contents.insert(contents.end(), candidates.begin(), candidates.end());
  for (size_t k = 0; contents.size() < free_count; ++k) {
    const Shade shade = shades[k % shades.size()];
    contents.push_back(MakePatch(PatchKind::kPalette, shade, options.palette[shade]));
  }
  if (contents.size() > free_count) {
    if (error) *error = "page too small for the palette repeats and the grey ramp";
    return std::nullopt;
  }
  return contents;
}

// Shuffles the contents by the sheet ID into the free slots, adds the paper and sizes each patch.
std::vector<Patch> PlacePatches(const Grid& grid, const CalibSheetOptions& options, int sheet_id,
                                std::vector<Patch> contents,
                                std::vector<std::pair<int, int>> free_slots,
                                const std::vector<std::pair<int, int>>& paper_slots) {
  std::mt19937 rng(static_cast<uint32_t>(sheet_id));
  Shuffle(&contents, &rng);
  for (const auto& [r, c] : paper_slots) {
    contents.push_back(MakePatch(PatchKind::kPaper, Shade::kWhite, Lab{100.0, 0.0, 0.0}));
    free_slots.push_back({r, c});
  }
  for (size_t i = 0; i < contents.size(); ++i) {
    Patch& patch = contents[i];
    patch.row = free_slots[i].first;
    patch.col = free_slots[i].second;
    patch.origin_mm = {grid.x0 + patch.col * grid.pitch, grid.y0 + patch.row * grid.pitch};
    patch.size_mm = options.patch_mm;
  }
  return contents;
}

// Reading order (row by row) for the sidecar and the report.
std::vector<Patch> InReadingOrder(std::vector<Patch> patches) {
  std::sort(patches.begin(), patches.end(), [](const Patch& a, const Patch& b) {
    return a.row != b.row ? a.row < b.row : a.col < b.col;
  });
  for (size_t i = 0; i < patches.size(); ++i) patches[i].index = static_cast<int>(i);
  return patches;
}

}  // namespace

bool CalibSheetOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (sheet_id < 0 || sheet_id > 65535) return fail("sheet ID must be in [1, 65535] (0: derived)");
  if (!(tag_size_mm >= 10 && tag_size_mm <= 60)) return fail("tag size must be in [10, 60] mm");
  if (!(patch_mm >= 6 && patch_mm <= 40)) return fail("patch size must be in [6, 40] mm");
  if (!(gap_mm >= 1 && gap_mm <= 20)) return fail("patch gap must be in [1, 20] mm");
  if (!(margin_mm >= 3 && margin_mm <= 50)) return fail("margin must be in [3, 50] mm");
  if (palette_repeats < 2 || palette_repeats > 20)
    return fail("palette repeats must be in [2, 20]");
  if (grey_levels < 3 || grey_levels > 20) return fail("grey levels must be in [3, 20]");
  if (candidate_a_offsets.empty() || candidate_b_steps < 2 || candidate_b_steps > 30 ||
      !(candidate_b_reach >= 0 && candidate_b_reach <= 60)) {
    return fail("candidate grid: at least one a* offset, 2 to 30 b* steps, b* reach in [0, 60]");
  }
  if (!(page.width_mm > 0 && page.height_mm > 0 && page.width_mm <= kMaxPageSideMm &&
        page.height_mm <= kMaxPageSideMm))
    return fail("page sides must be greater than zero and at most 10 m");
  return true;
}

std::optional<CalibSheetLayout> LayoutCalibSheet(const CalibSheetOptions& options,
                                                 std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  const auto grid = MakeGrid(options, error);
  if (!grid) return std::nullopt;
  auto family = TagFamily::Load("16h5");

  CalibSheetLayout layout;
  layout.sheet_id = options.sheet_id != 0 ? options.sheet_id : DerivedSheetId(options);
  layout.palette = options.palette;
  layout.page = options.page;
  layout.tag_size_mm = options.tag_size_mm;
  layout.rows = grid->rows;
  layout.columns = grid->columns;
  layout.tags = CornerTags(*grid, options, CornerIds(layout.sheet_id, *family));

  std::vector<bool> taken = TagSlots(*grid);
  const auto paper_slots = PaperSlots(*grid, &taken);
  std::vector<std::pair<int, int>> free_slots = FreeSlots(*grid, taken);
  auto contents = SlotContents(options, free_slots.size(), error);
  if (!contents) return std::nullopt;
  layout.patches = InReadingOrder(PlacePatches(
      *grid, options, layout.sheet_id, std::move(*contents), std::move(free_slots), paper_slots));
  return layout;
}

void DrawCalibPage(cairo_t* cr, const CalibSheetLayout& layout) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  const auto family = TagFamily::Load(layout.family);
  const TagColors colors = TagColors::FromPalette(layout.palette);
  TagDrawOptions tag_options;
  tag_options.quiet_zone_cells = 1;
  for (const CornerTag& tag : layout.tags) {
    DrawTag(cr, *family, tag.id, colors, tag.corners_mm[0][0], tag.corners_mm[0][1],
            layout.tag_size_mm, tag_options);
  }
  for (const Patch& patch : layout.patches) {
    if (patch.kind == PatchKind::kPaper) continue;
    const Rgb rgb = ToRgb(patch.rgb);
    cairo_set_source_rgb(cr, rgb.r, rgb.g, rgb.b);
    cairo_rectangle(cr, patch.origin_mm[0], patch.origin_mm[1], patch.size_mm, patch.size_mm);
    cairo_fill(cr);
  }
  const double x = layout.tags[0].corners_mm[0][0];
  const double top = layout.tags[0].corners_mm[0][1];
  cairo_set_source_rgb(cr, 0, 0, 0);
  char title[256];
  std::snprintf(title, sizeof(title),
                "ChromaTag calibration sheet %d    palette %s    print at 100 %%, colour "
                "management off",
                layout.sheet_id, layout.palette.name.c_str());
  DrawText(cr, x, top - 9.0, 3.2, title);
  double bottom = 0;
  for (const Patch& patch : layout.patches)
    bottom = std::max(bottom, patch.origin_mm[1] + patch.size_mm);
  char note[256];
  std::snprintf(note, sizeof(note),
                "Sheet %d: %zu patches in a pseudo-random order. Photograph the whole sheet, flat, "
                "without glare; keep its .json sidecar.",
                layout.sheet_id, layout.patches.size());
  cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
  DrawText(cr, x, bottom + 4.5, 2.4, note);
}

namespace {

// The page drawn on an RGB24 image surface; the caller destroys it.
cairo_surface_t* DrawCalibPageImage(const CalibSheetLayout& layout, double px_per_mm) {
  const int width = static_cast<int>(std::lround(layout.page.width_mm * px_per_mm));
  const int height = static_cast<int>(std::lround(layout.page.height_mm * px_per_mm));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cairo_t* cr = cairo_create(surface);
  cairo_scale(cr, px_per_mm, px_per_mm);
  DrawCalibPage(cr, layout);
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  return surface;
}

}  // namespace

cv::Mat RasterizeCalibPage(const CalibSheetLayout& layout, double px_per_mm) {
  cairo_surface_t* surface = DrawCalibPageImage(layout, px_per_mm);
  const int width = cairo_image_surface_get_width(surface);
  const int height = cairo_image_surface_get_height(surface);
  // RGB24 is a native-endian 32-bit word per pixel: B, G, R, unused in memory
  // on the little-endian machines this project builds for.
  const cv::Mat bgra(height, width, CV_8UC4, cairo_image_surface_get_data(surface),
                     static_cast<size_t>(cairo_image_surface_get_stride(surface)));
  cv::Mat bgr;
  cv::cvtColor(bgra, bgr, cv::COLOR_BGRA2BGR);
  cairo_surface_destroy(surface);
  return bgr;
}

std::vector<OutputFile> RenderCalibSheet(const CalibSheetLayout& layout, CalibSheetFormat format,
                                         const std::string& output_path, double dpi) {
  std::string bytes;
  if (format == CalibSheetFormat::kPdf) {
    cairo_surface_t* surface = cairo_pdf_surface_create_for_stream(
        AppendToString, &bytes, layout.page.width_mm * kPointsPerMm,
        layout.page.height_mm * kPointsPerMm);
    const std::string title = "ChromaTag calibration sheet " + std::to_string(layout.sheet_id);
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, title.c_str());
    const std::string creator = std::string("chromatag ") + kVersion;
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, creator.c_str());
    // No creation date: identical inputs give byte-identical files.
    cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATE_DATE, "");
    cairo_t* cr = cairo_create(surface);
    cairo_scale(cr, kPointsPerMm, kPointsPerMm);
    DrawCalibPage(cr, layout);
    cairo_show_page(cr);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    cairo_surface_destroy(surface);
  } else {
    cairo_surface_t* surface = DrawCalibPageImage(layout, dpi / 25.4);
    bytes = EncodePng(surface, dpi);
    cairo_surface_destroy(surface);
  }
  std::vector<OutputFile> files = {{output_path, bytes}};
  files.push_back({SidecarPath(output_path), CalibSidecarJson(layout, files)});
  return files;
}

}  // namespace chromatag
