// Sheets as printed: the PDF rasterised by poppler at 600 dpi, the PNG read
// back, and the sidecar compared with what is on the page.
#include "chromatag/generator/sheet.h"

#include "chromatag/base/sha256.h"
#include "chromatag/generator/sheet_request.h"
#include "chromatag/layout/sheet_record.h"

#include <gtest/gtest.h>
#include <poppler/cpp/poppler-document.h>
#include <poppler/cpp/poppler-page-renderer.h>
#include <poppler/cpp/poppler-page.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>

namespace chromatag {
namespace {

// An RGB raster of one page and its resolution.
struct Raster {
  int width = 0, height = 0;
  double px_per_mm = 0.0;
  std::vector<uint8_t> rgb;
  const uint8_t* At(int x, int y) const { return &rgb[(static_cast<size_t>(y) * width + x) * 3]; }
  double Luma(int x, int y) const {
    const uint8_t* p = At(x, y);
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
  }
};

std::string ReadFile(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

std::vector<Raster> RasterizePdf(const std::string& path, double dpi,
                                 std::vector<double>* sizes_pt) {
  std::unique_ptr<poppler::document> document(poppler::document::load_from_file(path));
  EXPECT_TRUE(document) << path;
  std::vector<Raster> pages;
  if (!document) return pages;
  poppler::page_renderer renderer;
  renderer.set_render_hint(poppler::page_renderer::antialiasing, true);
  for (int i = 0; i < document->pages(); ++i) {
    std::unique_ptr<poppler::page> page(document->create_page(i));
    const poppler::rectf box = page->page_rect();
    sizes_pt->push_back(box.width());
    sizes_pt->push_back(box.height());
    const poppler::image image = renderer.render_page(page.get(), dpi, dpi);
    Raster raster;
    raster.width = image.width();
    raster.height = image.height();
    raster.px_per_mm = dpi / 25.4;
    raster.rgb.resize(static_cast<size_t>(raster.width) * raster.height * 3);
    for (int y = 0; y < raster.height; ++y) {
      const auto* row =
          reinterpret_cast<const uint32_t*>(image.const_data() + y * image.bytes_per_row());
      for (int x = 0; x < raster.width; ++x) {
        uint8_t* out = &raster.rgb[(static_cast<size_t>(y) * raster.width + x) * 3];
        out[0] = static_cast<uint8_t>(row[x] >> 16);
        out[1] = static_cast<uint8_t>(row[x] >> 8);
        out[2] = static_cast<uint8_t>(row[x]);
      }
    }
    pages.push_back(std::move(raster));
  }
  return pages;
}

Raster ReadPng(const std::string& path, double dpi) {
  cairo_surface_t* surface = cairo_image_surface_create_from_png(path.c_str());
  Raster raster;
  raster.width = cairo_image_surface_get_width(surface);
  raster.height = cairo_image_surface_get_height(surface);
  raster.px_per_mm = dpi / 25.4;
  raster.rgb.resize(static_cast<size_t>(raster.width) * raster.height * 3);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  for (int y = 0; y < raster.height; ++y) {
    const auto* row = reinterpret_cast<const uint32_t*>(data + y * stride);
    for (int x = 0; x < raster.width; ++x) {
      uint8_t* out = &raster.rgb[(static_cast<size_t>(y) * raster.width + x) * 3];
      out[0] = static_cast<uint8_t>(row[x] >> 16);
      out[1] = static_cast<uint8_t>(row[x] >> 8);
      out[2] = static_cast<uint8_t>(row[x]);
    }
  }
  cairo_surface_destroy(surface);
  return raster;
}

// Sub-pixel position (pixel edges, mm) where luma crosses 128 along the row
// `y` between columns x_from and x_to (either direction); NaN if it does not.
double CrossingAlongRow(const Raster& r, int y, int x_from, int x_to) {
  const int step = x_to > x_from ? 1 : -1;
  for (int x = x_from; x != x_to; x += step) {
    const double a = r.Luma(x, y), b = r.Luma(x + step, y);
    if ((a - 128.0) * (b - 128.0) <= 0.0 && a != b) {
      // Pixel x's centre is at x + 0.5 in pixel-edge coordinates.
      const double t = (a - 128.0) / (a - b);
      return (x + 0.5 + step * t) / r.px_per_mm;
    }
  }
  return NAN;
}

double CrossingAlongColumn(const Raster& r, int x, int y_from, int y_to) {
  const int step = y_to > y_from ? 1 : -1;
  for (int y = y_from; y != y_to; y += step) {
    const double a = r.Luma(x, y), b = r.Luma(x, y + step);
    if ((a - 128.0) * (b - 128.0) <= 0.0 && a != b) {
      const double t = (a - 128.0) / (a - b);
      return (y + 0.5 + step * t) / r.px_per_mm;
    }
  }
  return NAN;
}

struct MeasuredSquare {
  double left, right, top, bottom;  // mm.
};

// Measures the black square of a tag whose sidecar corners are known: along
// the middle of the top and left black ring, from inside the ring outwards.
MeasuredSquare MeasureBlackSquare(const Raster& r, const nlohmann::json& tag, double cell_mm) {
  const double left = tag["corners_mm"][0][0], top = tag["corners_mm"][0][1];
  const double right = tag["corners_mm"][2][0], bottom = tag["corners_mm"][2][1];
  auto px = [&](double mm) { return static_cast<int>(std::floor(mm * r.px_per_mm)); };
  const int ring_y = px(top + cell_mm / 2), ring_x = px(left + cell_mm / 2);
  const int reach = px(cell_mm);  // Into the quiet zone.
  MeasuredSquare m;
  m.left = CrossingAlongRow(r, ring_y, px(left + cell_mm / 2), px(left) - reach);
  m.right = CrossingAlongRow(r, ring_y, px(right - cell_mm / 2), px(right) + reach);
  m.top = CrossingAlongColumn(r, ring_x, px(top + cell_mm / 2), px(top) - reach);
  m.bottom = CrossingAlongColumn(r, ring_x, px(bottom - cell_mm / 2), px(bottom) + reach);
  return m;
}

Rgb8 PixelAtMm(const Raster& r, double x_mm, double y_mm) {
  const uint8_t* p =
      r.At(static_cast<int>(x_mm * r.px_per_mm), static_cast<int>(y_mm * r.px_per_mm));
  return {p[0], p[1], p[2]};
}

// Reads the payload of a tag: every cell centre must be one of the palette's
// four chromatic shades exactly; returns the code, or -1 if a cell is not.
int64_t ReadPayload(const Raster& r, const nlohmann::json& tag, const TagFamily& family,
                    const Palette& palette, std::string* problem) {
  const double left = tag["corners_mm"][0][0], top = tag["corners_mm"][0][1];
  const double cell =
      (static_cast<double>(tag["corners_mm"][1][0]) - left) / family.black_square_cells();
  const int d = family.payload_width();
  Code code = 0;
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      const Rgb8 seen = PixelAtMm(r, left + (col + 1.5) * cell, top + (row + 1.5) * cell);
      const bool red = family.CellColorAt(row, col) == CellColor::kRed;
      const Rgb8 one = palette.Srgb8(red ? Shade::kRed1 : Shade::kGreen1);
      const Rgb8 zero = palette.Srgb8(red ? Shade::kRed0 : Shade::kGreen0);
      if (!(seen == one) && !(seen == zero)) {
        *problem = "cell (" + std::to_string(row) + ", " + std::to_string(col) + ") is " +
                   ToHex(seen) + ", expected " + ToHex(one) + " or " + ToHex(zero);
        return -1;
      }
      code = (code << 1) | (seen == one ? 1 : 0);
    }
  }
  return static_cast<int64_t>(code);
}

SheetOptions Options16h5All() {
  SheetOptions options;
  options.family = TagFamily::Load("16h5");
  options.ids = options.family->kept_ids();
  options.palette = *BuiltinPalette("default");
  options.tag_size_mm = 40.0;
  return options;
}

TEST(SheetTest, PdfAt600DpiHasExactSizesColoursIdsAndPositions) {
  const SheetOptions options = Options16h5All();
  const std::string path = ::testing::TempDir() + "/sheet_16h5.pdf";
  std::string error;
  ASSERT_TRUE(WriteSheet(options, path, &error)) << error;
  const auto sidecar = nlohmann::json::parse(ReadFile(SidecarPath(path)));
  std::vector<double> sizes_pt;
  const auto pages = RasterizePdf(path, 600.0, &sizes_pt);
  ASSERT_EQ(static_cast<int>(pages.size()), sidecar["page"]["count"].get<int>());
  for (size_t i = 0; i < sizes_pt.size(); i += 2) {
    EXPECT_NEAR(sizes_pt[i] * 25.4 / 72.0, 210.0, 1e-3);  // The page is exactly A4.
    EXPECT_NEAR(sizes_pt[i + 1] * 25.4 / 72.0, 297.0, 1e-3);
  }
  const double cell = sidecar["cell_size_mm"];
  std::map<int, int> found;
  for (const auto& tag : sidecar["tags"]) {
    const Raster& page = pages.at(tag["page"].get<int>() - 1);
    const MeasuredSquare m = MeasureBlackSquare(page, tag, cell);
    EXPECT_NEAR(m.right - m.left, 40.0, 0.1) << "ID " << tag["id"];
    EXPECT_NEAR(m.bottom - m.top, 40.0, 0.1) << "ID " << tag["id"];
    EXPECT_NEAR(m.left, tag["corners_mm"][0][0].get<double>(), 0.1);
    EXPECT_NEAR(m.top, tag["corners_mm"][0][1].get<double>(), 0.1);
    EXPECT_NEAR(m.right, tag["corners_mm"][2][0].get<double>(), 0.1);
    EXPECT_NEAR(m.bottom, tag["corners_mm"][2][1].get<double>(), 0.1);
    EXPECT_NEAR((m.left + m.right) / 2, tag["center_mm"][0].get<double>(), 0.1);
    std::string problem;
    const int64_t code = ReadPayload(page, tag, *options.family, options.palette, &problem);
    ASSERT_GE(code, 0) << "ID " << tag["id"] << ": " << problem;
    EXPECT_EQ(static_cast<Code>(code), options.family->CodeOf(tag["id"]));
    // The black ring and the quiet zone in their own colours too.
    const double left = tag["corners_mm"][0][0], top = tag["corners_mm"][0][1];
    EXPECT_EQ(PixelAtMm(page, left + cell / 2, top + 3 * cell), (Rgb8{0, 0, 0}));
    EXPECT_EQ(PixelAtMm(page, left - cell, top + 3 * cell), (Rgb8{255, 255, 255}));
    ++found[tag["id"]];
  }
  ASSERT_EQ(found.size(), options.ids.size());
  for (int id : options.ids) EXPECT_EQ(found[id], 1) << "ID " << id;
}

TEST(SheetTest, PngBlackSquareIsTheRequestedSizeWithinOnePixel) {
  for (const double size_mm : {25.4, 17.0}) {  // 50 px cells (snapped), and 33.46 px cells.
    SheetOptions options = Options16h5All();
    options.ids = {0, 3, 17};
    options.tag_size_mm = size_mm;
    options.format = SheetFormat::kPng;
    options.dpi = 300.0;
    const std::string path = ::testing::TempDir() + "/sheet_16h5.png";
    std::string error;
    ASSERT_TRUE(WriteSheet(options, path, &error)) << error;
    const Raster page = ReadPng(path, options.dpi);
    // The resolution is recorded: a pHYs chunk of 11811 pixels per metre.
    const std::string png = ReadFile(path);
    EXPECT_EQ(png.substr(37, 13), std::string("pHYs\0\0\x2e\x23\0\0\x2e\x23\x01", 13));
    EXPECT_EQ(page.width, 2480);  // A4 at 300 dpi.
    EXPECT_EQ(page.height, 3508);
    const auto sidecar = nlohmann::json::parse(ReadFile(SidecarPath(path)));
    ASSERT_EQ(sidecar["tags"].size(), 3u);
    const double expected_px = size_mm / 25.4 * 300.0;
    for (const auto& tag : sidecar["tags"]) {
      const MeasuredSquare m = MeasureBlackSquare(page, tag, sidecar["cell_size_mm"]);
      EXPECT_NEAR((m.right - m.left) * page.px_per_mm, expected_px, 1.0);
      EXPECT_NEAR((m.bottom - m.top) * page.px_per_mm, expected_px, 1.0);
      std::string problem;
      EXPECT_EQ(ReadPayload(page, tag, *options.family, options.palette, &problem),
                static_cast<int64_t>(options.family->CodeOf(tag["id"])))
          << problem;
      if (size_mm == 25.4) {
        // Whole-pixel cells: the pixels either side of the black square's
        // left edge are pure white and pure black.
        const int x =
            static_cast<int>(std::lround(tag["corners_mm"][0][0].get<double>() * page.px_per_mm));
        const int y = static_cast<int>(tag["center_mm"][1].get<double>() * page.px_per_mm);
        EXPECT_EQ(page.Luma(x - 1, y), 255.0);
        EXPECT_EQ(page.Luma(x, y), 0.0);
      }
    }
  }
}

TEST(SheetTest, IdenticalOptionsGiveIdenticalPdfAndPngBytes) {
  SheetOptions options = Options16h5All();
  options.ids = {1, 2};
  std::string error;
  const auto first = RenderSheet(options, "a.pdf", &error);
  const auto second = RenderSheet(options, "a.pdf", &error);
  ASSERT_TRUE(first && second) << error;
  ASSERT_EQ(first->size(), 2u);
  EXPECT_EQ((*first)[0].contents, (*second)[0].contents);
  EXPECT_EQ((*first)[1].contents, (*second)[1].contents);  // Sidecar.
  EXPECT_EQ((*first)[0].contents.find("CreationDate"), std::string::npos);
  // Metadata: title, subject with family, palette and size, palette values, creator.
  const std::string& pdf = (*first)[0].contents;
  std::unique_ptr<poppler::document> document(
      poppler::document::load_from_raw_data(pdf.data(), static_cast<int>(pdf.size())));
  ASSERT_TRUE(document);
  EXPECT_EQ(document->info_key("Title").to_latin1(), "ChromaTag 16h5 IDs 1-2");
  EXPECT_EQ(document->info_key("Subject").to_latin1(),
            "family 16h5; palette default; tag size (black square) 40.0 mm");
  EXPECT_NE(document->info_key("Keywords").to_latin1().find("red-1 52.00/79.00/18.25 #f30c61"),
            std::string::npos);
  EXPECT_EQ(document->info_key("Creator").to_latin1().rfind("chromatag ", 0), 0u);
}

TEST(SheetTest, SvgPagesAreSplitIntoFilesAndSizedInPoints) {
  SheetOptions options = Options16h5All();
  options.format = SheetFormat::kSvg;
  options.one_per_page = true;
  options.ids = {0, 1, 2};
  std::string error;
  const auto files = RenderSheet(options, "/tmp/x/tags.svg", &error);
  ASSERT_TRUE(files) << error;
  ASSERT_EQ(files->size(), 4u);
  EXPECT_EQ((*files)[1].path, "/tmp/x/tags-2.svg");
  EXPECT_EQ((*files)[3].path, "/tmp/x/tags.svg.json");
  EXPECT_NE((*files)[0].contents.find("width=\"595.275591pt\""), std::string::npos)
      << (*files)[0].contents.substr(0, 300);
}

TEST(SheetTest, ColourLutChangesTheWrittenColours) {
  // A 2x2x2 .cube that squeezes every channel into 0.2-0.8 (affine, so the
  // trilinear lookup is exact).
  const std::string lut_path = ::testing::TempDir() + "/squeeze.cube";
  {
    std::ofstream lut(lut_path);
    lut << "TITLE \"squeeze\"\nLUT_3D_SIZE 2\n";
    for (int b = 0; b < 2; ++b)
      for (int g = 0; g < 2; ++g)
        for (int r = 0; r < 2; ++r)
          lut << 0.2 + 0.6 * r << " " << 0.2 + 0.6 * g << " " << 0.2 + 0.6 * b << "\n";
  }
  std::string error;
  SheetOptions options = Options16h5All();
  options.ids = {0};
  options.format = SheetFormat::kPng;
  options.dpi = 150.0;
  options.color_lut = ColorLut::Load(lut_path, &error);
  ASSERT_TRUE(options.color_lut) << error;
  const std::string path = ::testing::TempDir() + "/lut.png";
  ASSERT_TRUE(WriteSheet(options, path, &error)) << error;
  const Raster page = ReadPng(path, options.dpi);
  const auto sidecar = nlohmann::json::parse(ReadFile(SidecarPath(path)));
  EXPECT_EQ(sidecar["color_lut"], "squeeze.cube");
  const auto& tag = sidecar["tags"][0];
  const double cell = sidecar["cell_size_mm"];
  const auto squeeze = [](uint8_t v) { return 255.0 * (0.2 + 0.6 * v / 255.0); };
  const auto near = [](const Rgb8& a, double r, double g, double b) {
    return std::abs(a.r - r) <= 1.0 && std::abs(a.g - g) <= 1.0 && std::abs(a.b - b) <= 1.0;
  };
  // Cell (0, 0) of ID 0 is green-0, squeezed; the black ring, dark grey.
  const Rgb8 green0 = options.palette.Srgb8(Shade::kGreen0);
  const double left = tag["corners_mm"][0][0], top = tag["corners_mm"][0][1];
  const Rgb8 cell00 = PixelAtMm(page, left + 1.5 * cell, top + 1.5 * cell);
  EXPECT_TRUE(near(cell00, squeeze(green0.r), squeeze(green0.g), squeeze(green0.b)))
      << int(cell00.r) << " " << int(cell00.g) << " " << int(cell00.b);
  EXPECT_EQ(sidecar["palette"]["written_rgb"]["green-0"], ToHex(cell00));
  const Rgb8 ring = PixelAtMm(page, left + 0.5 * cell, top + 0.5 * cell);
  EXPECT_TRUE(near(ring, 51, 51, 51)) << int(ring.r);
  std::remove(lut_path.c_str());
}

// A LUT that inverts the channels is one OpenColorIO reads, but it would
// print the black ring white and the shades swapped: refused, saying so.
TEST(SheetTest, AnInvertingLutIsRefused) {
  const std::string lut_path = ::testing::TempDir() + "/invert.cube";
  {
    std::ofstream lut(lut_path);
    lut << "LUT_3D_SIZE 2\n";
    for (int b = 0; b < 2; ++b)
      for (int g = 0; g < 2; ++g)
        for (int r = 0; r < 2; ++r) lut << 1 - r << " " << 1 - g << " " << 1 - b << "\n";
  }
  std::string error;
  EXPECT_FALSE(ColorLut::Load(lut_path, &error));
  EXPECT_NE(error.find("does not raise red with red (from 1 to 0"), std::string::npos) << error;
  std::remove(lut_path.c_str());
}

TEST(SheetTest, MalformedLutIsRefused) {
  const std::string lut_path = ::testing::TempDir() + "/broken.cube";
  {
    std::ofstream lut(lut_path);
    lut << "LUT_3D_SIZE 2\n0 0 0\nnot numbers\n";
  }
  std::string error;
  EXPECT_FALSE(ColorLut::Load(lut_path, &error));
  EXPECT_NE(error.find("is not a LUT OpenColorIO can read"), std::string::npos) << error;
  EXPECT_FALSE(ColorLut::Load("/nonexistent.cube", &error));
  EXPECT_EQ(error, "cannot read colour LUT '/nonexistent.cube': no such file");
  std::remove(lut_path.c_str());
}

TEST(SheetTest, LayoutRefusesTagsThatDoNotFitAndSaysWhy) {
  SheetOptions options = Options16h5All();
  options.tag_size_mm = 150.0;
  std::string error;
  EXPECT_FALSE(LayoutSheet(options, &error));
  EXPECT_EQ(error,
            "a 150.0 mm 16h5 tag needs 250.0 x 255.6 mm of paper with its quiet zone and label; "
            "page a4 (210.0 x 297.0 mm) with 10.0 mm margins and the scale bar leaves "
            "190.0 x 263.0 mm");
  options.tag_size_mm = 100.0;  // Fits, one per page.
  const auto layout = LayoutSheet(options, &error);
  ASSERT_TRUE(layout) << error;
  EXPECT_EQ(layout->columns * layout->rows, 1);
  EXPECT_EQ(layout->num_pages, 28);
}

TEST(SheetTest, GridFillsThePageWithoutOverlap) {
  SheetOptions options = Options16h5All();
  options.tag_size_mm = 20.0;
  options.crop_marks = true;
  options.tag.cut_ring = true;
  const auto layout = LayoutSheet(options);
  ASSERT_TRUE(layout);
  EXPECT_EQ(layout->columns, 3);  // 48 mm footprints with 5 mm gaps in 190 mm.
  EXPECT_EQ(layout->num_pages, 3);
  const double outer = 20.0 * 12 / 6;  // Quiet zones and cut ring: 12 cells.
  for (size_t i = 0; i < layout->tags.size(); ++i) {
    const auto& a = layout->tags[i];
    EXPECT_GE(a.corners_mm[0][0] - (outer - 20.0) / 2, options.margin_mm - 1e-9);
    for (size_t j = i + 1; j < layout->tags.size(); ++j) {
      const auto& b = layout->tags[j];
      if (a.page != b.page) continue;
      const bool apart = std::fabs(a.center_mm[0] - b.center_mm[0]) >= outer ||
                         std::fabs(a.center_mm[1] - b.center_mm[1]) >= outer;
      EXPECT_TRUE(apart) << a.id << " overlaps " << b.id;
    }
  }
}

TEST(SidecarTest, ReadsWhatWriteSheetWrote) {
  SheetOptions options = Options16h5All();
  options.ids = {3, 1, 2};
  options.format = SheetFormat::kSvg;
  options.one_per_page = true;
  const std::string path = ::testing::TempDir() + "/sidecar_read.svg";
  std::string error;
  ASSERT_TRUE(WriteSheet(options, path, &error)) << error;
  const auto record = ReadSidecar(SidecarPath(path), &error);
  ASSERT_TRUE(record) << error;
  EXPECT_EQ(record->family->name(), "16h5");
  EXPECT_EQ(record->num_pages, 3);
  ASSERT_EQ(record->files.size(), 3u);
  EXPECT_EQ(record->files[2].path, ::testing::TempDir() + "/sidecar_read-3.svg");
  EXPECT_EQ(record->files[0].sha256, Sha256Hex(ReadFile(path)));
  ASSERT_EQ(record->tags.size(), 3u);
  EXPECT_EQ(record->tags[0].id, 3);
  EXPECT_EQ(record->tags[2].page, 2);
  EXPECT_NEAR(record->palette[Shade::kRed1].b, 18.25, 1e-9);
}

TEST(SidecarTest, RefusesBrokenSidecarsNamingTheProblem) {
  const std::string path = ::testing::TempDir() + "/broken_sidecar.json";
  std::string error;
  std::ofstream(path) << "{\"schema\": \"something-else\"}";
  EXPECT_FALSE(ReadSidecar(path, &error));
  EXPECT_NE(error.find("not a ChromaTag sidecar"), std::string::npos) << error;
  std::ofstream(path) << "[1, 2";
  EXPECT_FALSE(ReadSidecar(path, &error));
  EXPECT_NE(error.find("not valid JSON"), std::string::npos) << error;
  std::ofstream(path) << "{\"schema\": \"chromatag-layout\", \"schema_version\": 1}";
  EXPECT_FALSE(ReadSidecar(path, &error));
  EXPECT_NE(error.find("missing \"family\""), std::string::npos) << error;
  EXPECT_FALSE(ReadSidecar("/nonexistent.json", &error));
  EXPECT_EQ(error, "cannot read sidecar '/nonexistent.json': no such file");
  std::remove(path.c_str());
}

}  // namespace
}  // namespace chromatag

namespace chromatag {
namespace {

SheetRequest BoardRequest(const std::string& board) {
  SheetRequest request;
  request.board = board;
  return request;
}

// A board fills its page: the largest whole-mm tags, the page turned when
// that fits larger ones, spacing a quarter of the size or the quiet zone,
// IDs in reading order, the origin at the bottom-left black square's
// bottom-left corner, recorded in the sidecar.
TEST(BoardSheetTest, FillsItsPageAndRecordsItsFrame) {
  SheetOptions options;
  std::string error;
  ASSERT_TRUE(ToSheetOptions(BoardRequest("6x4"), "b.pdf", &options, &error)) << error;
  ASSERT_TRUE(options.board);
  EXPECT_EQ(options.page.name, "a4 landscape");
  EXPECT_EQ(options.page.width_mm, 297.0);
  // Unless the orientation was asked for.
  SheetRequest portrait = BoardRequest("6x4");
  portrait.page = "a4-portrait";
  SheetOptions upright;
  ASSERT_TRUE(ToSheetOptions(portrait, "b.pdf", &upright, &error)) << error;
  EXPECT_EQ(upright.page.name, "a4 portrait");
  EXPECT_EQ(upright.page.width_mm, 210.0);
  EXPECT_LT(upright.tag_size_mm, options.tag_size_mm);
  EXPECT_EQ(options.tag_size_mm, std::floor(options.tag_size_mm));
  // 16h5's quiet zone (2 of 6 cells) is wider than a quarter.
  EXPECT_NEAR(options.board->spacing_mm, std::ceil(options.tag_size_mm / 3 * 10) / 10, 1e-9);
  ASSERT_EQ(options.ids.size(), 24u);
  EXPECT_EQ(options.ids, std::vector<int>(options.family->kept_ids().begin(),
                                          options.family->kept_ids().begin() + 24));
  const auto layout = LayoutSheet(options, &error);
  ASSERT_TRUE(layout) << error;
  EXPECT_EQ(layout->num_pages, 1);
  const double s = options.tag_size_mm, pitch = s + options.board->spacing_mm;
  for (int i = 0; i < 24; ++i) {
    const PlacedTag& tag = layout->tags[i];
    EXPECT_NEAR(tag.corners_mm[0][0], layout->tags[0].corners_mm[0][0] + (i % 6) * pitch, 1e-9);
    EXPECT_NEAR(tag.corners_mm[0][1], layout->tags[0].corners_mm[0][1] + (i / 6) * pitch, 1e-9);
  }
  EXPECT_EQ(layout->board_origin_mm, layout->tags[18].corners_mm[3]);
  // One more millimetre does not fit.
  SheetOptions larger = options;
  larger.tag_size_mm += 1;
  larger.board->spacing_mm = std::ceil(larger.tag_size_mm / 3 * 10) / 10;
  EXPECT_FALSE(LayoutSheet(larger, &error));
  EXPECT_NE(error.find("give no tag size for the largest that fits"), std::string::npos) << error;

  const auto files = RenderSheet(options, "b.pdf", &error);
  ASSERT_TRUE(files) << error;
  const auto record = ParseSidecar(files->back().contents, "", &error);
  ASSERT_TRUE(record) << error;
  ASSERT_TRUE(record->board);
  EXPECT_EQ(record->board->columns, 6);
  EXPECT_EQ(record->board->rows, 4);
  EXPECT_NEAR(record->board_origin_mm[0], layout->board_origin_mm[0], 1e-3);
  EXPECT_NEAR(record->board_origin_mm[1], layout->board_origin_mm[1], 1e-3);
  // A board's tags carry no label.
  EXPECT_FALSE(nlohmann::json::parse(files->back().contents)["label"].get<bool>());
  // A sidecar whose board disagrees with its tags is refused.
  for (const auto& [path, value, what] :
       std::vector<std::tuple<std::string, nlohmann::json, std::string>>{
           {"/board/origin_mm", {0.0, 0.0}, "origin_mm is not the bottom-left tag's"},
           {"/board/spacing_mm", -1.0, "spacing_mm must be positive"},
           {"/board/columns", 4, "columns x rows"},
           {"/tags/5/corners_mm/0/0", 3.0, "not on its columns x rows grid"}}) {
    nlohmann::json tampered = nlohmann::json::parse(files->back().contents);
    tampered[nlohmann::json::json_pointer(path)] = value;
    if (path == "/board/columns") tampered["board"]["rows"] = 6;
    EXPECT_FALSE(ParseSidecar(tampered.dump(), "", &error)) << path;
    EXPECT_NE(error.find(what), std::string::npos) << error;
  }
  // A sheet that is not a board: the page's bottom-left corner.
  SheetOptions sheet = Options16h5All();
  const auto sheet_files = RenderSheet(sheet, "s.pdf", &error);
  const auto sheet_record = ParseSidecar(sheet_files->back().contents, "", &error);
  ASSERT_TRUE(sheet_record) << error;
  EXPECT_FALSE(sheet_record->board);
  EXPECT_EQ(sheet_record->board_origin_mm, (std::array<double, 2>{0.0, 297.0}));
}

TEST(BoardSheetTest, RefusesWhatIsNoBoardAndSaysWhy) {
  SheetOptions options;
  std::string error;
  const auto refused = [&](SheetRequest request, const std::string& what) {
    const bool ok = ToSheetOptions(request, "b.pdf", &options, &error);
    EXPECT_FALSE(ok) << request.board;
    EXPECT_NE(error.find(what), std::string::npos) << error;
    // In the library's terms: the command line adds its flags' names.
    EXPECT_EQ(error.find("--"), std::string::npos) << error;
  };
  refused(BoardRequest("6y4"), "the board must be COLSxROWS");
  refused(BoardRequest("0x4"), "the board must be COLSxROWS");
  refused(BoardRequest("7x5"), "16h5 keeps 28 IDs");
  refused(BoardRequest("99999999999x1"), "the board must be COLSxROWS");
  refused(BoardRequest(" 2x 2"), "the board must be COLSxROWS");
  SheetRequest ids = BoardRequest("2x2");
  ids.ids = "0-2";
  refused(ids, "holds 4 tags, but 3 IDs");
  // A spacing too small for any tag's quiet zone names the spacing, not
  // a tag size that was never given.
  SheetRequest narrow = BoardRequest("6x4");
  narrow.quiet_zone = 20;
  narrow.spacing = "1mm";
  refused(narrow, "a spacing of 1.0 mm holds the quiet zone of tags of at most 0.30 mm");
  SheetRequest tight = BoardRequest("2x2");
  tight.size = "30mm";
  tight.spacing = "5mm";
  refused(tight, "at least their quiet zone, 10.0 mm");
  // Without a size, a given spacing bounds it: 5 mm holds the quiet zone of
  // 15 mm 16h5 tags (2 of 6 cells).
  SheetRequest spaced = BoardRequest("2x2");
  spaced.spacing = "5mm";
  ASSERT_TRUE(ToSheetOptions(spaced, "b.pdf", &options, &error)) << error;
  EXPECT_EQ(options.tag_size_mm, 15.0);
  SheetRequest zero = BoardRequest("2x2");
  zero.spacing = "0mm";
  refused(zero, "the spacing: ");
  SheetRequest big = BoardRequest("6x4");
  big.size = "40mm";
  ASSERT_TRUE(ToSheetOptions(big, "b.pdf", &options, &error)) << error;
  EXPECT_FALSE(LayoutSheet(options, &error));
  EXPECT_NE(error.find("a 6x4 board of 40.0 mm tags 13.4 mm apart needs"), std::string::npos)
      << error;
  // A size that fits the page neither way says what both leave.
  EXPECT_NE(error.find("leaves 190.0 x 263.0 mm, turned 277.0 x 176.0 mm"), std::string::npos)
      << error;
  SheetRequest spacing;
  spacing.ids = "0";
  spacing.spacing = "5mm";
  refused(spacing, "a spacing is for boards");
  SheetRequest ring = BoardRequest("2x2");
  ring.cut_ring = true;
  refused(ring, "no tag per page, cut ring or crop marks");
}

}  // namespace
}  // namespace chromatag
