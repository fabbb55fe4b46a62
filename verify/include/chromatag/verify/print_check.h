// `chromatag verify --print`: checking the printed sheet itself from scans
// and photos of its pages. The file's own round trip
// (sheet_check.h) proves that the file decodes; this finds what printing did
// to it: a page shrunk by "fit to page", a stretched axis, shades washed out
// until the detector cannot split them, a tag printed with its shades
// swapped.
//
// Per image: the tags of the sheet are detected, the page they belong to is
// found from their IDs, and one transform from page millimetres to pixels is
// fitted over all of them (robust to a misread or missing tag): an affine map
// for a flatbed scan, whose resolution is known, so its scale is absolute; a
// homography for a photo, where only the page's aspect can be told. Every
// tag of that page is then measured where the fit puts it, found or not: its
// four shades in CIELAB normalised to the white of its own quiet zone, and
// their gaps against what the detector needs.
#ifndef CHROMATAG_VERIFY_PRINT_CHECK_H_
#define CHROMATAG_VERIFY_PRINT_CHECK_H_

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detector.h"
#include "chromatag/families/margins.h"
#include "chromatag/families/palette.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/sheet_check.h"

namespace chromatag {

struct PrintCheckOptions {
  // The images are flatbed scans: their resolution is known, so the printed
  // size is checked. Otherwise they are photos (any perspective).
  bool scans = false;
  // Resolution of the scans, pixels per inch; 0 reads it from each file (a
  // PNG's pHYs chunk, a JPEG's JFIF density). [50, 4800] when set.
  double scan_dpi = 0.0;
  // Largest accepted error of a scan's printed scale, relative: 0.005 lets a
  // 40 mm tag print between 39.8 and 40.2 mm. (0, 0.2].
  double max_scale_error = 0.005;
  // Largest accepted difference between the page's x and y scales in a
  // photo, relative (photos tell the aspect, not the size). (0, 0.2].
  double max_aspect_error = 0.02;
  // Largest distance, mm, between a found tag's corners and where the fit
  // over the other tags puts them before the tag is flagged as misplaced
  // (a sheet not flat, a page slipped in the printer). (0, 50].
  double max_position_error_mm = 1.0;
  // The detector whose needs the shades are judged against (thresholds from
  // `--config`); its families are ignored: both are looked for.
  DetectorOptions detector;
  // Photos: the camera's intrinsics make the aspect exact; without them the
  // focal length is estimated from the page's perspective.
  std::optional<CameraIntrinsics> camera;
  // Margins below these warn: the tag decodes here but has little to spare
  // for dimmer light, blur or a cast, by the same measures the colour
  // calibration keeps (families/margins.h): a b* gap under the thin one, or
  // a gap under the safety factor times what the detector needs.
  double thin_b_gap = kThinShadeGap;
  double thin_factor = kMarginSafetyFactor;

  bool IsValid(std::string* error) const;
};

enum class Grade { kPass = 0, kWarn, kFail };
const char* GradeName(Grade grade);  // "pass", "warn", "fail".

// One tag's shades as printed and seen.
struct PrintedShades {
  bool measured = false;
  // Index: Shade (red-1, red-0, green-1, green-0); lab normalised to the
  // paper white of the tag's quiet zone, as_shot as the image holds it.
  std::array<ShadeReading, 4> shades;
  Lab paper_as_shot;  // The quiet zone's white, as shot.
  Margins margins;    // MarginsOf the normalised shades.
};

struct PrintTagResult {
  PlacedTag expected;
  bool found = false;  // A detection of the sheet's family lies on it.
  int found_id = -1;
  int hamming = 0;
  double margin = 0.0;  // The detector's decision margin.
  // Black square, spec order: detected, or where the page fit puts it.
  std::array<cv::Point2d, 4> corners_px{};
  PrintedShades colours;
  // Scans: the black square's mean side as printed, mm (0 when not found).
  double size_mm = 0.0;
  // Found tags: worst corner's distance, mm on the page, from where a fit
  // over the other tags puts it.
  double position_error_mm = 0.0;
  Grade grade = Grade::kPass;
  std::vector<std::string> problems;  // Worst first; empty when it passes.
  std::vector<Grade> problem_grades;  // Each problem's own.
};

// A tag-like candidate that did not decode, in an image where no tag of the
// sheet did: its red and green cells' b* splits tell why.
struct UndecodedCandidate {
  std::array<cv::Point2d, 4> corners_px{};
  double red_b_split = 0.0;  // Largest gap between the red cells' sorted b*.
  double green_b_split = 0.0;
  double a_gap = 0.0;  // Median red a* minus median green a*.
};

struct PrintPageResult {
  std::string image;  // Its name, as given.
  cv::Size image_size;
  int page = -1;  // The sheet's page (from 0) it shows; -1 if none was recognised.
  bool scan = false;
  double dpi_x = 0.0, dpi_y = 0.0;  // Scans.
  // Page millimetres (sidecar convention) to image pixels (centres at
  // integers): affine for scans, projective for photos (to undistorted
  // pixels when the camera's distortion is given).
  cv::Matx33d image_from_page = cv::Matx33d::eye();
  int tags_found = 0;   // With the right ID.
  int tags_in_fit = 0;  // Tags whose corners the fit kept.
  double rms_mm = 0.0;  // Fit residual over those corners, on the page.
  // Scans: printed size over the sidecar's along the page's x and y axes,
  // their standard errors from the fit (one; the text and the report show
  // two, at least 0.001), and how far the axes are from square, degrees.
  double scale_x = 0.0, scale_y = 0.0;
  double scale_x_error = 0.0, scale_y_error = 0.0;
  double skew_deg = 0.0;
  // Photos: the page's x scale over its y scale (0 when too few tags fit
  // to judge it) and its standard error (jackknife over the tags); the
  // focal length used and where it came from: "camera" (given),
  // "perspective" (from the page's own perspective) or "guessed" (a face-on
  // view, where it barely matters).
  double aspect = 0.0;
  double aspect_error = 0.0;
  double focal_px = 0.0;
  std::string focal_source;
  // Whether the page's shape (scale or aspect) was judged: false for an
  // image whose page was not recognised or whose tags fit no layout, and
  // for a photo with too few tags or whose view leaves the aspect's
  // uncertainty over the tolerance without showing it off (then a warning
  // says so).
  bool geometry_checked = false;
  Grade grade = Grade::kPass;         // The page's and its tags' worst.
  std::vector<std::string> problems;  // About the page as a whole.
  std::vector<Grade> problem_grades;  // Each problem's own.
  std::vector<PrintTagResult> tags;   // The page's tags, in sidecar order.
  std::vector<UnexpectedDetection> unexpected;
  std::vector<UndecodedCandidate> undecoded;
  // The image resampled onto the page (BGR) at view_px_per_mm (3, fewer
  // for pages over 1.3 m), for reports; empty when the page was not
  // recognised.
  cv::Mat page_view;
  double view_px_per_mm = 0.0;
};

struct PrintVerdict {
  std::vector<PrintPageResult> images;
  std::vector<int> pages_not_seen;  // Pages (from 0) no image showed.
  int tags_checked = 0;
  int tags_passed = 0;  // Pass or warn.
  int tags_warned = 0;
  Grade grade = Grade::kPass;
  bool passed() const { return grade != Grade::kFail; }
};

// One scan or photo to check.
struct PrintImage {
  std::string name;
  // A scan's resolution, pixels per inch; 0 for a photo.
  double dpi_x = 0.0, dpi_y = 0.0;
  bool dpi_from_file = false;  // Read from the file's header, not given.
};

// Checks one image (CV_8UC3 BGR) of a printed page of `record`'s sheet.
// `detector` should look for both families (and report rejected
// candidates, for the diagnosis when no tag decodes).
PrintPageResult CheckPrintImage(const SheetRecord& record, const cv::Mat& bgr,
                                const PrintImage& image, const Detector& detector,
                                const PrintCheckOptions& options);

// The sidecar of the printed sheet: `path` is the sheet (.pdf, .svg, .png),
// whose sidecar must be beside it and describe it, or the sidecar itself
// (.json). Refuses (nullopt, *error) what ReadSidecar refuses, a missing
// sheet, a sidecar of another sheet, and a tag size or page outside
// (0, 10 m].
std::optional<SheetRecord> ReadPrintedSheet(const std::string& path, std::string* error = nullptr);

// Reads each image and checks it. Refuses (nullopt, *error) bad options, an
// unreadable image, or a scan whose resolution is neither given nor in its
// file, or lies outside [50, 4800] dpi.
std::optional<PrintVerdict> CheckPrintFiles(const SheetRecord& record,
                                            const std::vector<std::string>& paths,
                                            const PrintCheckOptions& options,
                                            std::string* error = nullptr);

// The resolution an image file records, pixels per inch (x, y): a PNG's
// pHYs chunk in pixels per metre; a JPEG's EXIF XResolution and YResolution
// (IFD0, through libexif) in inches or centimetres, else its JFIF density in
// dots per inch or centimetre; a TIFF's XResolution and YResolution in
// inches or centimetres. nullopt when it records none (or only an aspect
// ratio).
std::optional<std::array<double, 2>> ReadImageDpi(const std::string& bytes);

// The verdict as one JSON object (docs/verify.md): per image the page, the
// scale or aspect and the problems, per tag its grade, detection, measured
// CIELAB shades and gaps. Invalid UTF-8 in names is replaced.
std::string PrintVerdictJson(const SheetRecord& record, const PrintVerdict& verdict);

// The report drawn: per image, the page as seen with every tag marked pass,
// warn or fail and the page's numbers. PDF one page per image; PNG the
// images' pages in rows of four, at most kMaxPngReportImages (beyond, the
// PNG is empty: use a PDF). Returns the file's bytes.
inline constexpr int kMaxPngReportImages = 80;
std::string RenderPrintReportPdf(const SheetRecord& record, const PrintVerdict& verdict);
std::string RenderPrintReportPng(const SheetRecord& record, const PrintVerdict& verdict);

}  // namespace chromatag

#endif  // CHROMATAG_VERIFY_PRINT_CHECK_H_
