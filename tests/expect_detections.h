// Shared by the detector's condition tests: a detector looking for both
// families, and a check that every tag of a synthetic scene is found exactly
// once with its family and ID and its outer and inner ring corners within a
// bound, and nothing else.
#ifndef CHROMATAG_TESTS_EXPECT_DETECTIONS_H_
#define CHROMATAG_TESTS_EXPECT_DETECTIONS_H_

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "chromatag/detector/detector.h"
#include "chromatag/families/family.h"
#include "synthetic_scene.h"

namespace chromatag::testing {

inline std::unique_ptr<Detector> BothFamiliesDetector() {
  DetectorOptions options;
  options.families = {"16h5", "36h11"};
  return Detector::Create(options);
}

inline void ExpectEveryTagFoundOnce(const Detector& detector, const Scene& scene,
                                    double max_corner_px, const std::string& what) {
  const DetectionResult result = detector.Detect(scene.bgr);
  EXPECT_EQ(result.detections.size(), scene.truth.size()) << what;
  for (const TagTruth& truth : scene.truth) {
    int found = 0;
    for (const Detection& d : result.detections) {
      if (d.family->name() != truth.family || d.id != truth.id) continue;
      ++found;
      EXPECT_LT(MaxCornerError(d.corners, truth.corners), max_corner_px)
          << what << ": " << truth.family << " ID " << truth.id;
      const int cells = d.family->black_square_cells();
      EXPECT_LT(MaxCornerError(d.green_corners, InnerCorners(truth, cells, 1)), max_corner_px)
          << what << ": " << truth.family << " ID " << truth.id << ", green/black corners";
      EXPECT_LT(MaxCornerError(d.red_corners, InnerCorners(truth, cells, 2)), max_corner_px)
          << what << ": " << truth.family << " ID " << truth.id << ", red/green corners";
    }
    EXPECT_EQ(found, 1) << what << ": " << truth.family << " ID " << truth.id;
  }
}

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_EXPECT_DETECTIONS_H_
