// Reading the scans and photos of verify --print, and the printed sheet's
// sidecar (print_check.h).
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <filesystem>
#include <memory>

#include <libexif/exif-data.h>
#include <poppler/cpp/poppler-document.h>

#include "chromatag/base/input_file.h"
#include "chromatag/base/output_files.h"
#include "chromatag/base/sha256.h"
#include "chromatag/detector/read_image.h"
#include "chromatag/verify/print_check.h"
#include "poppler_messages.h"
#include "print_internal.h"

namespace chromatag {
namespace {

bool EndsWithJson(const std::string& path) { return LowerExtension(path) == ".json"; }

// A TIFF's XResolution and YResolution (rationals) in its ResolutionUnit
// (2 inch, the default; 3 centimetre), from the first IFD; either byte order.
std::optional<std::array<double, 2>> TiffDpi(const std::string& bytes) {
  if (bytes.size() < 8) return std::nullopt;
  const bool little = bytes.compare(0, 4, "II*\0", 4) == 0;
  if (!little && bytes.compare(0, 4, "MM\0*", 4) != 0) return std::nullopt;
  auto u8 = [&](size_t i) { return static_cast<uint32_t>(static_cast<unsigned char>(bytes[i])); };
  auto u16 = [&](size_t i) { return little ? u8(i) | (u8(i + 1) << 8) : (u8(i) << 8) | u8(i + 1); };
  auto u32 = [&](size_t i) {
    return little ? u16(i) | (u16(i + 2) << 16) : (u16(i) << 16) | u16(i + 2);
  };
  const size_t ifd = u32(4);
  if (ifd > bytes.size() || bytes.size() - ifd < 2) return std::nullopt;
  const size_t entries = u16(ifd);
  if ((bytes.size() - ifd - 2) / 12 < entries) return std::nullopt;
  double x = 0, y = 0;
  uint32_t unit = 2;
  for (size_t e = 0; e < entries; ++e) {
    const size_t at = ifd + 2 + 12 * e;
    const uint32_t tag = u16(at), type = u16(at + 2), count = u32(at + 4);
    if ((tag == 282 || tag == 283) && type == 5 && count == 1) {
      const size_t value = u32(at + 8);
      if (value > bytes.size() || bytes.size() - value < 8) return std::nullopt;
      const uint32_t num = u32(value), den = u32(value + 4);
      if (den == 0) return std::nullopt;
      (tag == 282 ? x : y) = static_cast<double>(num) / den;
    } else if (tag == 296 && type == 3 && count == 1) {
      unit = u16(at + 8);
    }
  }
  if (!(x > 0 && y > 0) || (unit != 2 && unit != 3)) return std::nullopt;
  const double f = unit == 2 ? 1.0 : 2.54;
  return std::array<double, 2>{x * f, y * f};
}

// The resolution an EXIF block records (a JPEG's APP1 payload, from its
// "Exif\0\0" header), read through libexif: IFD0's XResolution and
// YResolution in its ResolutionUnit (2 inch, the default; 3 centimetre).
// IFD1's are the thumbnail's.
std::optional<std::array<double, 2>> ExifDpi(const unsigned char* data, size_t size) {
  const std::unique_ptr<ExifData, void (*)(ExifData*)> exif(exif_data_new(), exif_data_unref);
  if (!exif) return std::nullopt;
  // Without FOLLOW_SPECIFICATION (on by default): it would fill in the
  // mandatory tags a file lacks, XResolution 72 among them.
  exif_data_unset_option(exif.get(), EXIF_DATA_OPTION_FOLLOW_SPECIFICATION);
  exif_data_load_data(exif.get(), data, static_cast<unsigned int>(size));
  const ExifByteOrder order = exif_data_get_byte_order(exif.get());
  ExifContent* ifd0 = exif->ifd[EXIF_IFD_0];
  if (!ifd0) return std::nullopt;
  auto rational = [&](ExifTag tag) {
    const ExifEntry* e = exif_content_get_entry(ifd0, tag);
    if (!e || e->format != EXIF_FORMAT_RATIONAL || e->components != 1 || !e->data || e->size < 8)
      return 0.0;
    const ExifRational r = exif_get_rational(e->data, order);
    return r.denominator == 0 ? 0.0 : static_cast<double>(r.numerator) / r.denominator;
  };
  const double x = rational(EXIF_TAG_X_RESOLUTION), y = rational(EXIF_TAG_Y_RESOLUTION);
  unsigned unit = 2;
  if (const ExifEntry* e = exif_content_get_entry(ifd0, EXIF_TAG_RESOLUTION_UNIT)) {
    const bool ok = e->format == EXIF_FORMAT_SHORT && e->components == 1 && e->data && e->size >= 2;
    unit = ok ? exif_get_short(e->data, order) : 0;
  }
  if (!(x > 0 && y > 0) || (unit != 2 && unit != 3)) return std::nullopt;
  const double f = unit == 2 ? 1.0 : 2.54;
  return std::array<double, 2>{x * f, y * f};
}

}  // namespace

std::optional<SheetRecord> ReadPrintedSheet(const std::string& path, std::string* error) {
  auto record = EndsWithJson(path) ? ReadSidecar(path, error) : ReadSheetSidecar(path, error);
  if (!record) return std::nullopt;
  std::string why;
  if (!internal::SheetIsSane(*record, &why)) {
    if (error) *error = "sidecar '" + record->sidecar_path + "': " + why;
    return std::nullopt;
  }
  // The sheet files beside the sidecar (all of them when the sheet is given)
  // must be the ones it was written with, and hold the pages it lists: a
  // sidecar edited afterwards would judge the print against other tags.
  const auto fail = [&](const std::string& message) -> std::optional<SheetRecord> {
    if (error) *error = "sidecar '" + record->sidecar_path + "' " + message;
    return std::nullopt;
  };
  for (const SheetRecord::File& file : record->files) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file.path, ec)) {
      if (!EndsWithJson(path)) return fail("lists '" + file.path + "', which is not there");
      continue;  // The sidecar alone, as the docs allow.
    }
    const auto bytes = ReadInputFile(file.path, "sheet", std::uintmax_t{512} << 20, error);
    if (!bytes) return std::nullopt;
    if (Sha256Hex(*bytes) != file.sha256) {
      return fail("does not match '" + file.path +
                  "': the sheet's SHA-256 differs from the one recorded (the sheet or the sidecar "
                  "was changed after they were written)");
    }
    if (record->format != SheetFormat::kPdf) continue;  // One file a page.
    PopplerMessages messages;
    std::unique_ptr<poppler::document> pdf(poppler::document::load_from_raw_data(
        bytes->data(), static_cast<int>(std::min<size_t>(bytes->size(), INT_MAX))));
    if (pdf && pdf->pages() != record->num_pages) {
      return fail("lists " + std::to_string(record->num_pages) + " page(s), and '" + file.path +
                  "' has " + std::to_string(pdf->pages()));
    }
  }
  return record;
}

std::optional<std::array<double, 2>> ReadImageDpi(const std::string& bytes) {
  auto u8 = [&](size_t i) { return static_cast<uint32_t>(static_cast<unsigned char>(bytes[i])); };
  auto be16 = [&](size_t i) { return (u8(i) << 8) | u8(i + 1); };
  auto be32 = [&](size_t i) { return (be16(i) << 16) | be16(i + 2); };
  static const char kPng[] = "\x89PNG\r\n\x1a\n";
  if (bytes.size() >= 8 && bytes.compare(0, 8, kPng, 8) == 0) {
    // Chunks: length, type, data, CRC; pHYs comes before the first IDAT.
    size_t at = 8;
    while (at + 8 <= bytes.size()) {
      const uint32_t length = be32(at);
      const std::string type = bytes.substr(at + 4, 4);
      if (type == "IDAT" || type == "IEND" || length > bytes.size() - at - 8) break;
      if (type == "pHYs" && length == 9 && u8(at + 16) == 1) {
        const double x = be32(at + 8), y = be32(at + 12);
        if (x > 0 && y > 0) return std::array<double, 2>{x * 0.0254, y * 0.0254};
        return std::nullopt;
      }
      at += 12 + static_cast<size_t>(length);
    }
    return std::nullopt;
  }
  if (bytes.size() >= 4 && u8(0) == 0xFF && u8(1) == 0xD8) {
    // Segments: FF marker, length (including itself); JFIF is an APP0, EXIF
    // an APP1, both before the scan (SOS).
    std::optional<std::array<double, 2>> jfif;
    bool jfif_seen = false, exif_seen = false;
    size_t at = 2;
    while (at + 4 <= bytes.size() && u8(at) == 0xFF && !(jfif_seen && exif_seen)) {
      const uint32_t marker = u8(at + 1), length = be16(at + 2);
      if (marker == 0xDA || length < 2 || at + 2 + length > bytes.size()) break;
      if (marker == 0xE0 && !jfif_seen && length >= 16 &&
          bytes.compare(at + 4, 5, "JFIF\0", 5) == 0) {
        jfif_seen = true;
        const uint32_t units = u8(at + 11);
        const double x = be16(at + 12), y = be16(at + 14);
        if (x > 0 && y > 0 && (units == 1 || units == 2)) {
          const double f = units == 1 ? 1.0 : 2.54;
          jfif = std::array<double, 2>{x * f, y * f};
        }
      } else if (marker == 0xE1 && !exif_seen && length >= 8 &&
                 bytes.compare(at + 4, 6, "Exif\0\0", 6) == 0) {
        exif_seen = true;
        // EXIF's resolution wins over JFIF's density: cameras and scanners
        // set EXIF's, while JFIF's is often an encoder's default (72 dpi,
        // or units 0: aspect only) that nobody updates.
        const auto* payload = reinterpret_cast<const unsigned char*>(bytes.data()) + at + 4;
        if (const auto dpi = ExifDpi(payload, length - 2)) return dpi;
      }
      at += 2 + length;
    }
    return jfif;
  }
  return TiffDpi(bytes);
}

namespace {

// A scan's resolution: the one given, else the one its file records (which
// must lie in [50, 4800] dpi); false with *error when there is none.
bool ScanDpi(const std::string& path, const std::string& bytes, const PrintCheckOptions& options,
             PrintImage* image, std::string* error) {
  if (options.scan_dpi > 0) {
    image->dpi_x = image->dpi_y = options.scan_dpi;
    return true;
  }
  const auto dpi = ReadImageDpi(bytes);
  if (!dpi) {
    if (error) {
      *error = "scan '" + path + "' does not record its resolution; give the scanner's resolution";
    }
    return false;
  }
  image->dpi_x = (*dpi)[0];
  image->dpi_y = (*dpi)[1];
  image->dpi_from_file = true;
  if (!(std::min(image->dpi_x, image->dpi_y) >= 50.0 &&
        std::max(image->dpi_x, image->dpi_y) <= 4800.0)) {
    if (error) {
      *error = "scan '" + path + "' records " + std::to_string(std::lround(image->dpi_x)) + " x " +
               std::to_string(std::lround(image->dpi_y)) +
               " dpi, outside [50, 4800]; give the scanner's resolution";
    }
    return false;
  }
  return true;
}

}  // namespace

std::optional<PrintVerdict> CheckPrintFiles(const SheetRecord& record,
                                            const std::vector<std::string>& paths,
                                            const PrintCheckOptions& options, std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  if (paths.empty()) {
    if (error) *error = "give at least one scan or photo of the printed sheet";
    return std::nullopt;
  }
  DetectorOptions detector_options = options.detector;
  detector_options.families = TagFamily::Names();
  detector_options.report_rejected = true;
  detector_options.camera.reset();
  detector_options.tag_size = 0.0;
  auto detector = Detector::Create(detector_options, error);
  if (!detector) return std::nullopt;
  PrintVerdict verdict;
  std::vector<bool> seen(record.num_pages, false);
  for (const std::string& path : paths) {
    const auto bytes = ReadInputFile(path, "image", kMaxImageFileBytes, error);
    if (!bytes) return std::nullopt;
    cv::Mat bgr = DecodeImage(*bytes, path, error);
    if (bgr.empty()) return std::nullopt;
    PrintImage image;
    image.name = path;
    if (options.scans && !ScanDpi(path, *bytes, options, &image, error)) return std::nullopt;
    PrintPageResult page = CheckPrintImage(record, bgr, image, *detector, options);
    if (page.page >= 0 && page.page < record.num_pages) seen[page.page] = true;
    verdict.grade = std::max(verdict.grade, page.grade);
    for (const PrintTagResult& t : page.tags) {
      ++verdict.tags_checked;
      verdict.tags_passed += t.grade != Grade::kFail;
      verdict.tags_warned += t.grade == Grade::kWarn;
    }
    verdict.images.push_back(std::move(page));
  }
  for (int p = 0; p < record.num_pages; ++p)
    if (!seen[p]) verdict.pages_not_seen.push_back(p);
  return verdict;
}

}  // namespace chromatag
