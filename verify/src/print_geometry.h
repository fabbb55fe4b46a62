// The print check's geometry (print_check.h): which page of the sheet an
// image shows, the one transform from page millimetres to the image fitted
// over its tags' corners (affine for a scan, projective for a photo, robust
// to a misplaced tag), what it says of the print (a scan's scale and skew, a
// photo's aspect), how far each tag lies from where the others put it, and
// the image resampled onto the page for the report.
#ifndef CHROMATAG_VERIFY_SRC_PRINT_GEOMETRY_H_
#define CHROMATAG_VERIFY_SRC_PRINT_GEOMETRY_H_

#include <array>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/verify/print_check.h"

namespace chromatag::internal {

inline constexpr double kMmPerInch = 25.4;

// Where the page is fitted: scan millimetres for a scan; for a photo,
// pixels, undistorted when the camera's distortion is known.
class FitSpace {
 public:
  FitSpace(const PrintImage& image, const std::optional<CameraIntrinsics>& camera);
  bool scan() const { return scan_; }

  // An image pixel into fit space, and fit space points back to pixels.
  cv::Point2d FromImage(const cv::Point2d& px) const;
  std::vector<cv::Point2d> ToImage(const std::vector<cv::Point2d>& points) const;
  // From fit space to undistorted pixels (for image_from_page).
  cv::Matx33d PixelsFromFit() const;

 private:
  bool scan_;
  double mm_per_px_x_, mm_per_px_y_;
  std::optional<CameraIntrinsics> camera_;  // A photo through a lens with distortion.
};

// A detection of the sheet's family paired with a tag of the page by ID.
struct Pair {
  int tag = 0;        // Index into the page's tags.
  int detection = 0;  // Index into the detections.
};

// Page millimetres to fit space, over the pairs' corners.
struct PageFit {
  cv::Matx33d image_from_page = cv::Matx33d::eye();
  std::vector<int> kept;  // Pairs the fit kept.
  double rms_mm = 0.0;
  // Scans: the affine's parameters' standard errors (x and y columns).
  double se_x = 0.0, se_y = 0.0;
};

// The page of the sheet most detections belong to, by ID; -1 for none.
int ChoosePage(const SheetRecord& record, const std::vector<const Detection*>& mine);

// Detections paired with the page's tags by ID. Only IDs the page holds
// once pair (generate never repeats an ID); a tag whose ID appears twice in
// a hand-made sidecar is still found afterwards, by its place on the page.
std::vector<Pair> PairByIds(const std::vector<PlacedTag>& tags,
                            const std::vector<const Detection*>& mine);

// Fits over every pair's four corners (`found_corners` in fit space, per
// detection), then drops the tag that lies worst off the fit while it lies
// more than `drop_mm` off, refitting each time (never below two tags).
// Residuals are measured on the page. Affine or projective; nullopt when
// the corners give no fit.
std::optional<PageFit> FitPage(const std::vector<PlacedTag>& tags,
                               const std::vector<std::array<cv::Point2d, 4>>& found_corners,
                               const std::vector<Pair>& pairs, bool affine, double drop_mm);

// The scan's printed scale along the page's axes, their standard errors
// and their skew, from its (affine) fit.
void MeasureScale(const PageFit& fit, PrintPageResult* r);

// A photo's aspect, from the kept tags' corners on the page and in
// (undistorted) pixels, four a tag, with its jackknife standard error over
// the tags, and the focal length used and where it came from.
void MeasureAspect(const std::vector<cv::Point2d>& page, const std::vector<cv::Point2d>& image,
                   const std::optional<CameraIntrinsics>& camera, cv::Size size,
                   PrintPageResult* r);

// The worst corner distance, mm on the page, of pair `k`'s tag from where a
// fit over the other kept pairs puts it (from the full fit when it was left
// out of it, or when too few others remain).
double LeaveOneOutError(const std::vector<PlacedTag>& tags,
                        const std::vector<std::array<cv::Point2d, 4>>& fit_corners,
                        const std::vector<Pair>& pairs, const PageFit& fit, int k, bool affine);

// The image resampled onto the page, `s` pixels a millimetre, through
// `fit_from_page` and `space`; grey where the image ends.
cv::Mat PageView(const cv::Mat& bgr, const cv::Matx33d& fit_from_page, const FitSpace& space,
                 const PageSize& page, double s);

}  // namespace chromatag::internal

#endif  // CHROMATAG_VERIFY_SRC_PRINT_GEOMETRY_H_
