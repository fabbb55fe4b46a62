// Finding the calibration sheet through its corner tags (locate_sheet.h).
#include "chromatag/calib/locate_sheet.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/detector.h"

namespace chromatag {
namespace {

std::string IdList(const std::vector<int>& ids) {
  std::string out;
  for (size_t i = 0; i < ids.size(); ++i) out += (i ? ", " : "") + std::to_string(ids[i]);
  return out;
}

// The corner tags of `layout` found in `detections`, by corner (-1: missing).
// Several detections of one ID keep the one with the largest margin.
std::array<int, 4> MatchCorners(const CalibSheetLayout& layout,
                                const std::vector<Detection>& detections) {
  std::array<int, 4> match = {-1, -1, -1, -1};
  for (int k = 0; k < 4; ++k) {
    for (size_t i = 0; i < detections.size(); ++i) {
      const Detection& d = detections[i];
      if (d.family->name() != layout.family || d.id != layout.tags[k].id) continue;
      if (match[k] < 0 || d.decision_margin > detections[match[k]].decision_margin)
        match[k] = static_cast<int>(i);
    }
  }
  return match;
}

int Count(const std::array<int, 4>& match) {
  int n = 0;
  for (int m : match) n += m >= 0;
  return n;
}

std::string DescribeFailure(const CalibSheetLayout& layout,
                            const std::vector<Detection>& detections,
                            const std::array<int, 4>& match) {
  std::vector<int> expected, others;
  for (const CornerTag& tag : layout.tags) expected.push_back(tag.id);
  for (const Detection& d : detections) {
    bool ours = false;
    for (int id : expected) ours |= d.family->name() == layout.family && d.id == id;
    if (!ours) others.push_back(d.id);
  }
  const std::string sheet = "sheet " + std::to_string(layout.sheet_id);
  if (detections.empty()) {
    return "no ChromaTag found: the calibration sheet is not in the photo, or it is too small, "
           "blurred, dark or washed out to find its corner tags";
  }
  if (Count(match) == 0) {
    return "this is not " + sheet + ": the photo shows " + layout.family + " tags " +
           IdList(others) + ", but its corner tags are " + IdList(expected) +
           " (a different calibration sheet, or the wrong sheet's sidecar)";
  }
  std::string missing;
  for (int k = 0; k < 4; ++k) {
    if (match[k] >= 0) continue;
    missing += (missing.empty() ? "" : ", ") + std::string(kCornerNames[k]) + " (ID " +
               std::to_string(layout.tags[k].id) + ")";
  }
  return "only " + std::to_string(Count(match)) + " of the 4 corner tags of " + sheet +
         " found, missing " + missing + ": the whole sheet must be in the photo";
}

// A copy of the photo made easier to search, for locating only: white-balanced
// on its brightest pixels (the paper) and with its chroma multiplied, so that
// the corner tags of a washed-out print in dim or tinted light still show the
// a* rise and the red the detector looks for. Measuring uses the original.
cv::Mat Enhanced(const cv::Mat& bgr, double chroma_gain) {
  std::vector<cv::Mat> channels;
  cv::split(bgr, channels);
  cv::Mat f;
  bgr.convertTo(f, CV_32FC3, 1.0 / 255.0);
  cv::Scalar gains;
  for (int c = 0; c < 3; ++c) {
    // The 97th percentile of each channel: the paper, if the sheet fills a
    // fair part of the photo.
    int histogram[256] = {};
    for (int y = 0; y < channels[c].rows; ++y) {
      const uint8_t* row = channels[c].ptr<uint8_t>(y);
      for (int x = 0; x < channels[c].cols; ++x) ++histogram[row[x]];
    }
    const double target = 0.97 * channels[c].total();
    int level = 0;
    for (double seen = 0; level < 255 && seen + histogram[level] < target; ++level)
      seen += histogram[level];
    gains[c] = 0.92 / std::max(level, 8) * 255.0;
  }
  cv::multiply(f, gains, f);
  cv::min(f, 1.0, f);
  cv::Mat lab;
  cv::cvtColor(f, lab, cv::COLOR_BGR2Lab);
  cv::multiply(lab, cv::Scalar(1.0, chroma_gain, chroma_gain), lab);
  cv::cvtColor(lab, f, cv::COLOR_Lab2BGR);
  cv::Mat out;
  f.convertTo(out, CV_8UC3, 255.0);
  return out;
}

}  // namespace

bool LocateOptions::IsValid(std::string* error) const {
  if (threshold_ladder.empty()) {
    if (error) *error = "the threshold ladder needs at least one rung";
    return false;
  }
  for (const auto& rung : threshold_ladder) {
    if (!(rung[0] > 0 && rung[0] <= 200 && rung[1] > 0 && rung[1] <= 100)) {
      if (error)
        *error = "ladder thresholds must be ADiffThresh in (0, 200], BorderThresh (0, 100]";
      return false;
    }
  }
  if (!(enhance_chroma >= 1 && enhance_chroma <= 5)) {
    if (error) *error = "enhance_chroma must be in [1, 5]";
    return false;
  }
  if (!(max_rms_mm > 0 && max_rms_mm <= 10)) {
    if (error) *error = "max_rms_mm must be in (0, 10]";
    return false;
  }
  return true;
}

cv::Point2d PageToImage(const cv::Matx33d& image_from_page, const std::array<double, 2>& mm) {
  const cv::Vec3d p = image_from_page * cv::Vec3d(mm[0], mm[1], 1.0);
  return {p[0] / p[2], p[1] / p[2]};
}

namespace {

// The photo's detections on the first threshold rung (the photo as it is,
// then with its chroma raised) that finds all four corner tags, else the
// rung that matched most; the rung's thresholds into *location. False only
// when a detector cannot be made.
bool FindCornerTags(const cv::Mat& bgr, const CalibSheetLayout& layout,
                    const LocateOptions& options, std::vector<Detection>* best_detections,
                    std::array<int, 4>* best_corners, SheetLocation* location, std::string* error) {
  std::vector<Detection>& best = *best_detections;
  std::array<int, 4>& best_match = *best_corners;
  cv::Mat enhanced;
  for (int attempt = 0; attempt < 2 && Count(best_match) < 4; ++attempt) {
    if (attempt == 1) enhanced = Enhanced(bgr, options.enhance_chroma);
    const cv::Mat& image = attempt == 0 ? bgr : enhanced;
    for (const auto& rung : options.threshold_ladder) {
      DetectorOptions detector_options;
      detector_options.families = {layout.family};
      detector_options.adiff_thresh = rung[0];
      detector_options.border_thresh = rung[1];
      // The sheet is known to be there: accept weaker decodes than for
      // tracking; the four IDs and their arrangement are checked below.
      detector_options.min_decision_margin = 1.0;
      auto detector = Detector::Create(detector_options, error);
      if (!detector) return false;
      std::vector<Detection> detections = detector->Detect(image).detections;
      const auto match = MatchCorners(layout, detections);
      if (Count(match) > Count(best_match) || (best.empty() && !detections.empty())) {
        best = detections;
        best_match = match;
        location->adiff_thresh = rung[0];
        location->border_thresh = rung[1];
        location->enhanced = attempt == 1;
      }
      if (Count(best_match) == 4) break;
    }
  }
  return true;
}

// The homography from page millimetres to the photo over the four corner
// tags' corners, and its residual; false with *error when they fit no one
// flat sheet.
bool FitSheet(const CalibSheetLayout& layout, const std::vector<Detection>& best,
              const std::array<int, 4>& best_match, const LocateOptions& options,
              SheetLocation* location, std::string* error) {
  std::vector<cv::Point2d> page_points, image_points;
  for (int k = 0; k < 4; ++k) {
    const Detection& d = best[best_match[k]];
    for (int i = 0; i < 4; ++i) {
      page_points.push_back({layout.tags[k].corners_mm[i][0], layout.tags[k].corners_mm[i][1]});
      image_points.push_back(d.corners[i]);
    }
  }
  const cv::Mat h = cv::findHomography(page_points, image_points, 0);
  if (h.empty()) {
    if (error) *error = "the corner tags do not fit one plane";
    return false;
  }
  location->image_from_page = cv::Matx33d(h);
  // Residuals in page millimetres through the local scale of the fit.
  double sum_sq = 0, scale_sum = 0;
  for (size_t i = 0; i < page_points.size(); ++i) {
    const std::array<double, 2> mm = {page_points[i].x, page_points[i].y};
    const cv::Point2d p = PageToImage(location->image_from_page, mm);
    const cv::Point2d q = PageToImage(location->image_from_page, {mm[0] + 1.0, mm[1]});
    const double scale = cv::norm(q - p);
    scale_sum += scale;
    sum_sq += std::pow(cv::norm(p - image_points[i]) / scale, 2);
  }
  location->rms_mm = std::sqrt(sum_sq / page_points.size());
  location->px_per_mm = scale_sum / page_points.size();
  if (location->rms_mm > options.max_rms_mm) {
    if (error) {
      char text[200];
      std::snprintf(text, sizeof(text),
                    "the corner tags do not lie on one flat sheet (%.2f mm RMS, at most %.2f): "
                    "flatten the sheet, or photograph it from further away",
                    location->rms_mm, options.max_rms_mm);
      *error = text;
    }
    return false;
  }
  return true;
}

}  // namespace

std::optional<SheetLocation> LocateSheet(const cv::Mat& bgr, const CalibSheetLayout& layout,
                                         const LocateOptions& options, std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  if (bgr.empty() || bgr.type() != CV_8UC3) {
    if (error) *error = "the photo must be an 8-bit colour image";
    return std::nullopt;
  }
  std::vector<Detection> best;
  std::array<int, 4> best_match = {-1, -1, -1, -1};
  SheetLocation location;
  if (!FindCornerTags(bgr, layout, options, &best, &best_match, &location, error))
    return std::nullopt;
  if (Count(best_match) < 4) {
    if (error) *error = DescribeFailure(layout, best, best_match);
    return std::nullopt;
  }
  if (!FitSheet(layout, best, best_match, options, &location, error)) return std::nullopt;
  return location;
}

}  // namespace chromatag
