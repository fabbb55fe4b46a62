// `chromatag verify --stress`: each tag seen through simulated camera
// conditions, to find the weakest IDs before anyone prints them.
#ifndef CHROMATAG_VERIFY_STRESS_H_
#define CHROMATAG_VERIFY_STRESS_H_

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/detector.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag {

// A simulated view of one tag on a light grey background.
struct ViewParams {
  double size_px = 100.0;          // Side of the black square when seen face on, pixels.
  double tilt_deg = 0.0;           // Rotation of the tag about its horizontal axis.
  double roll_deg = 0.0;           // In-plane rotation.
  double blur_sigma = 0.0;         // Gaussian blur, pixels.
  double noise_sigma = 0.0;        // Gaussian noise, 8-bit levels.
  int jpeg_quality = 0;            // 1..100; 0 for none.
  cv::Vec3d gains{1.0, 1.0, 1.0};  // White-balance cast: R, G, B multipliers.
  bool bayer = false;              // RGGB mosaic then OpenCV's demosaic.
  uint64_t seed = 1;
};

// Renders the view as an 8-bit BGR frame (pinhole camera, f = 800 px), and
// the black square's corners in it (ground truth, spec section 7 order).
cv::Mat RenderView(const TagFamily& family, int id, const TagColors& colors,
                   const ViewParams& params, std::array<cv::Point2d, 4>* corners = nullptr);

struct StressOptions {
  std::vector<double> tilts_deg = {0, 10, 20, 30, 40, 50, 60};
  double tilt_size_px = 120.0;  // Size the tilt sweep is seen at.
  double largest_size_px = 160.0;
  double smallest_size_px = 6.0;
  double size_step = 0.85;          // Each size is this times the last.
  double condition_size_px = 60.0;  // Size the other conditions are seen at.
};

struct ConditionOutcome {
  std::string condition;  // "blur 1.5 px", "JPEG q40", ...
  bool decoded = false;
};

struct TagStress {
  int id = 0;
  double smallest_size_px = 0.0;   // Smallest face-on size that still decodes; 0 if none.
  double largest_tilt_deg = -1.0;  // Largest tilt that still decodes; -1 if none.
  std::vector<ConditionOutcome> conditions;
  bool all_conditions_decoded = false;
};

// A decode counts when the detector finds exactly one tag, with the right ID.
TagStress StressTag(const TagFamily& family, int id, const TagColors& colors,
                    const Detector& detector, const StressOptions& options = {});

// The stress results as a JSON array (one line; the "stress" of `chromatag
// verify --stress --json`): per tag its id, smallest_size_px,
// largest_tilt_deg and conditions (each condition's name: decoded or not).
std::string StressJson(const std::vector<TagStress>& stresses);

}  // namespace chromatag

#endif  // CHROMATAG_VERIFY_STRESS_H_
