// The detector on synthetic scenes (tests/synthetic_scene.h) and on tag-free
// photographs: detection, decoding, orientation and corner accuracy.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "chromatag/detector/detector.h"
#include "synthetic_scene.h"

namespace chromatag {
namespace {

using testing::RenderScene;
using testing::Scene;
using testing::SceneOptions;
using testing::SceneTag;

std::unique_ptr<Detector> MakeDetector(std::vector<std::string> families = {"16h5", "36h11"}) {
  DetectorOptions options;
  options.families = std::move(families);
  std::string error;
  auto detector = Detector::Create(options, &error);
  EXPECT_TRUE(detector) << error;
  return detector;
}

TEST(DetectorSceneTest, FindsOneUprightTag) {
  auto detector = MakeDetector();
  SceneTag tag;
  tag.centre = {160, 120};
  Scene scene = RenderScene({tag}, {});
  DetectionResult result = detector->Detect(scene.bgr);
  ASSERT_EQ(result.detections.size(), 1u);
  const Detection& d = result.detections[0];
  EXPECT_EQ(d.family, "16h5");
  EXPECT_EQ(d.id, 0);
  for (int i = 0; i < 4; ++i) {
    std::printf("%d: %.3f %.3f truth %.3f %.3f\n", i, d.corners[i].x, d.corners[i].y,
                scene.truth[0].corners[i].x, scene.truth[0].corners[i].y);
  }
  EXPECT_LT(testing::MaxCornerError(d.corners, scene.truth[0].corners), 0.5);
}

}  // namespace
}  // namespace chromatag
