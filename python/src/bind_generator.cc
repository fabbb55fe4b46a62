// Tags and sheets: render_tag, generate, and the families and palettes.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/generator/sheet_request.h"
#include "chromatag/generator/tag_renderer.h"
#include "common.h"

namespace chromatag::python {
namespace {

py::array RenderTag(const std::string& family_name, int id, double cell_px,
                    const std::string& palette_name, int quiet_zone, const std::string& order) {
  std::string error;
  const auto family = TagFamily::Load(family_name, &error);
  if (!family) throw Error(error);
  if (!family->IsValidId(id, &error)) throw Error(error);
  const auto palette = BuiltinPalette(palette_name, &error);
  if (!palette) throw Error(error);
  if (!(cell_px >= 1.0 && cell_px <= 1000.0))
    throw Error("cell_px must lie in [1, 1000] pixels per cell");
  if (quiet_zone < 1 || quiet_zone > 20) throw Error("quiet_zone must lie in [1, 20] cells");
  const PixelOrder pixel_order = OrderFrom(order);
  TagDrawOptions draw;
  draw.quiet_zone_cells = quiet_zone;
  const RgbImage rgb = RasterizeTag(*family, id, TagColors::FromPalette(*palette), cell_px, draw);
  py::array_t<uint8_t> out({rgb.height, rgb.width, 3});
  auto view = out.mutable_unchecked<3>();
  for (int y = 0; y < rgb.height; ++y) {
    for (int x = 0; x < rgb.width; ++x) {
      const uint8_t* p = rgb.At(x, y);
      for (int c = 0; c < 3; ++c) view(y, x, c) = p[pixel_order == PixelOrder::kRgb ? c : 2 - c];
    }
  }
  return out;
}

std::vector<std::string> Generate(
    const std::filesystem::path& output_path, const std::string& family, const py::object& ids,
    const std::string& size, const std::string& page, const std::string& margin,
    const std::string& gap, int quiet_zone, const std::string& palette,
    const std::filesystem::path& palette_file_path, const std::filesystem::path& color_lut_path,
    const std::string& format, double dpi, bool label, bool crop_marks, bool cut_ring,
    bool one_per_page, const std::string& board, const std::string& spacing) {
  const std::string output = output_path.string(), palette_file = palette_file_path.string(),
                    color_lut = color_lut_path.string();
  SheetRequest request;
  request.family = family;
  request.board = board;
  request.spacing = spacing;
  if (ids.is_none()) {
    request.all = board.empty();  // A board takes the family's first kept IDs.
  } else if (py::isinstance<py::str>(ids)) {
    request.ids = ids.cast<std::string>();
  } else if (py::isinstance<py::int_>(ids)) {
    request.ids = std::to_string(Arg<int>(ids, "ids", "tag IDs (small integers)"));
  } else {
    for (const py::handle& id : ids)
      request.ids += (request.ids.empty() ? "" : ",") +
                     std::to_string(Arg<int>(id, "ids", "tag IDs (small integers)"));
    if (request.ids.empty()) throw Error("ids is empty: give some IDs, or None for every kept ID");
  }
  request.size = size;
  request.page = page;
  request.margin = margin;
  request.gap = gap;
  request.quiet_zone = quiet_zone;
  request.palette = palette;
  request.palette_file = palette_file;
  request.color_lut = color_lut;
  request.format = format;
  request.dpi = dpi;
  request.label = label;
  request.crop_marks = crop_marks;
  request.cut_ring = cut_ring;
  request.one_per_page = one_per_page;
  SheetOptions options;
  std::string error;
  if (!ToSheetOptions(request, output, &options, &error)) throw Error(error);
  std::vector<std::string> written;
  bool ok = false;
  {
    py::gil_scoped_release release;
    ok = WriteSheet(options, output, &error, &written);
  }
  if (!ok) throw Error(error);
  return written;
}

py::dict FamilyInfo(const std::string& name) {
  std::string error;
  const auto family = TagFamily::Load(name, &error);
  if (!family) throw Error(error);
  py::dict out;
  out["name"] = family->name();
  out["payload_width"] = family->payload_width();
  out["black_square_cells"] = family->black_square_cells();
  out["min_hamming"] = family->min_hamming();
  out["kept_ids"] = family->kept_ids();
  return out;
}

py::dict PaletteInfo(const std::string& name) {
  std::string error;
  const auto palette = BuiltinPalette(name, &error);
  if (!palette) throw Error(error);
  py::dict shades;
  for (Shade shade : kAllShades) {
    const Lab& lab = (*palette)[shade];
    const Rgb8 rgb = palette->Srgb8(shade);
    py::dict entry;
    entry["lab"] = py::make_tuple(lab.L, lab.a, lab.b);
    entry["srgb"] = py::make_tuple(rgb.r, rgb.g, rgb.b);
    shades[ShadeName(shade)] = entry;
  }
  py::dict out;
  out["name"] = palette->name;
  out["description"] = palette->description;
  out["shades"] = shades;
  return out;
}

}  // namespace

void BindGenerator(py::module_& m) {
  m.def("render_tag", &RenderTag, py::arg("family"), py::arg("id"), py::arg("cell_px") = 10.0,
        py::arg("palette") = "default", py::arg("quiet_zone") = 2, py::arg("order") = "bgr",
        "One tag with its quiet zone as an H x W x 3 uint8 image, cell_px pixels per cell.");
  m.def("generate", &Generate, py::arg("output"), py::kw_only(), py::arg("family") = "16h5",
        py::arg("ids") = py::none(), py::arg("size") = "", py::arg("page") = "a4",
        py::arg("margin") = "10mm", py::arg("gap") = "5mm", py::arg("quiet_zone") = 2,
        py::arg("palette") = "default", py::arg("palette_file") = "", py::arg("color_lut") = "",
        py::arg("format") = "", py::arg("dpi") = 300.0, py::arg("label") = true,
        py::arg("crop_marks") = false, py::arg("cut_ring") = false, py::arg("one_per_page") = false,
        py::arg("board") = "", py::arg("spacing") = "",
        "Writes a print-ready sheet (PDF, SVG or PNG, from the extension) and its sidecar\n"
        "(output + '.json'), as 'chromatag generate' does; ids: a list, '0-9,12', or None for\n"
        "every kept ID (a board: its first COLS * ROWS). size: default 40mm, or for a board\n"
        "the largest that fits. board: 'COLSxROWS' lays the tags out as a board whose sidecar\n"
        "is its board file (Board.from_file). Returns the paths written.");
  m.def("families", &TagFamily::Names, "The families: ['16h5', '36h11']");
  m.def("family", &FamilyInfo, py::arg("name"), "A family's geometry, distance and kept IDs");
  m.def("palettes", &BuiltinPaletteNames, "The built-in palettes");
  m.def("palette", &PaletteInfo, py::arg("name"), "A palette's six shades in CIELAB and sRGB");
}

}  // namespace chromatag::python
