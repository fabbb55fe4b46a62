// The detector under camera conditions that used to lose tags: Gaussian blur
// of 1.5-2 px on 60-120 px tags (blurred edges ended scans half way down the
// slope), a strong cool cast (which parts the two reds' a* by 12 units) and
// JPEG at quality 40 (chroma blur and blocking). Every kept 16h5 ID must
// decode, and tags printed with swapped shades must still never decode.
#include <gtest/gtest.h>

#include <cmath>

#include "chromatag/detector/detector.h"
#include "chromatag/families/family.h"
#include "expect_detections.h"
#include "synthetic_scene.h"

namespace chromatag {
namespace {

using testing::ExpectEveryTagFoundOnce;
using testing::RenderScene;
using testing::Scene;
using testing::SceneOptions;
using testing::SceneTag;
using testing::TagTruth;

std::unique_ptr<Detector> MakeDetector() {
  DetectorOptions options;
  options.families = {"16h5", "36h11"};
  return Detector::Create(options);
}

// All kept IDs of `family_name` in one frame, `size` px black squares turned
// 7 degrees (off the pixel grid, as verify's stress views) plus a little per
// ID, laid out with a two-cell quiet zone and room to spare.
std::vector<SceneTag> Grid(const std::string& family_name, double size, int columns,
                           const std::string& palette, bool swap_shades, SceneOptions* options) {
  const auto family = TagFamily::Load(family_name);
  const std::vector<int>& ids = family->kept_ids();
  const double pitch = std::ceil(size * 1.9);
  std::vector<SceneTag> tags;
  for (size_t i = 0; i < ids.size(); ++i) {
    SceneTag tag;
    tag.family = family_name;
    tag.id = ids[i];
    tag.black_square_px = size;
    tag.centre = {pitch * (0.5 + static_cast<double>(i % columns)) + 0.3,
                  pitch * (0.5 + static_cast<double>(i / columns)) - 0.2};
    tag.rotation_deg = 7 + 13 * (i % 4);
    tag.palette = palette;
    tag.swap_shades = swap_shades;
    tags.push_back(tag);
  }
  options->width = static_cast<int>(pitch * columns);
  options->height = static_cast<int>(pitch * ((ids.size() + columns - 1) / columns));
  return tags;
}

TEST(DetectorConditionsTest, BlurOfOneAndAHalfToTwoPixelsOnSixtyTo120PixelTags) {
  auto detector = MakeDetector();
  for (double blur : {1.5, 2.0}) {
    for (double size : {60., 80., 100., 120.}) {
      SceneOptions options;
      const std::vector<SceneTag> tags = Grid("16h5", size, 7, "default", false, &options);
      options.blur_sigma = blur;
      options.noise_sigma = 1;
      options.seed = static_cast<unsigned>(size);
      // Symmetric blur leaves the halfway level on the edge: corners stay
      // sub-pixel.
      ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 0.5,
                              "blur " + std::to_string(blur) + " size " + std::to_string(size));
    }
  }
}

TEST(DetectorConditionsTest, BlurredTiltedTagsOfBothFamilies) {
  auto detector = MakeDetector();
  const int kIds16h5[] = {1, 6, 9, 13, 17, 21};
  for (const std::string name : {"16h5", "36h11"}) {
    std::vector<SceneTag> tags;
    for (int k = 0; k < 6; ++k) {
      SceneTag tag;
      tag.family = name;
      tag.id = name == "16h5" ? kIds16h5[k] : 97 * k + 5;
      tag.black_square_px = 70 + 10 * k;
      tag.centre = {100.0 + 200 * (k % 3), 100.0 + 200 * (k / 3)};
      tag.rotation_deg = 50.0 * k + 7;
      tag.tilt_deg = 35;
      tag.tilt_axis_deg = 30.0 * k;
      tags.push_back(tag);
    }
    SceneOptions options;
    options.width = 600;
    options.height = 400;
    options.blur_sigma = 1.5;
    options.noise_sigma = 2;
    ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 1.0, name + " tilted, blur 1.5");
  }
}

TEST(DetectorConditionsTest, StrongCoolCastAndJpegQuality40) {
  auto detector = MakeDetector();
  struct Condition {
    std::string name;
    cv::Vec3d gain;
    int jpeg_quality;
  };
  const Condition conditions[] = {{"cool cast", {0.75, 1, 1.3}, 0},
                                  {"warm cast", {1.25, 1, 0.7}, 0},
                                  {"JPEG q40", {1, 1, 1}, 40},
                                  {"cool cast and JPEG q60", {0.8, 1, 1.25}, 60}};
  for (const Condition& c : conditions) {
    SceneOptions options;
    const std::vector<SceneTag> tags = Grid("16h5", 60, 7, "default", false, &options);
    options.gain = c.gain;
    options.jpeg_quality = c.jpeg_quality;
    options.noise_sigma = 1;
    ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 1.0, c.name);
  }
}

// Swapped shades show each tag's complement within each colour; under blur,
// noise, casts and JPEG (which compress and scatter the 16h5 red centre's four
// cells) that must still never decode, in either palette.
TEST(DetectorConditionsTest, SwappedShadesNeverDecodeUnderBlurNoiseCastsAndJpeg) {
  auto detector = MakeDetector();
  struct Condition {
    double size, blur, noise;
    cv::Vec3d gain;
    int jpeg_quality;
  };
  const Condition conditions[] = {{46, 2.0, 0, {1, 1, 1}, 50},   {50, 2.5, 2, {1, 1, 1}, 0},
                                  {60, 1.5, 3, {1, 1, 1}, 0},    {60, 0, 8, {1, 1, 1}, 0},
                                  {60, 0, 4, {0.75, 1, 1.3}, 0}, {80, 0, 0, {1.25, 1, 0.7}, 60},
                                  {60, 0, 0, {1, 1, 1}, 40},     {100, 2.0, 2, {1, 1, 1}, 0}};
  int decoded = 0, tags_seen = 0;
  for (const std::string palette : {"default", "iccv17"}) {
    unsigned seed = 1;
    for (const Condition& c : conditions) {
      SceneOptions options;
      const std::vector<SceneTag> tags = Grid("16h5", c.size, 7, palette, true, &options);
      options.blur_sigma = c.blur;
      options.noise_sigma = c.noise;
      options.gain = c.gain;
      options.jpeg_quality = c.jpeg_quality;
      options.seed = seed++;
      const DetectionResult result = detector->Detect(RenderScene(tags, options).bgr);
      for (const Detection& d : result.detections) {
        ADD_FAILURE() << palette << " size " << c.size << " blur " << c.blur << " noise " << c.noise
                      << ": a swapped tag decoded as " << d.family->name() << " " << d.id
                      << " (hamming " << d.hamming << ", margin " << d.decision_margin << ")";
        ++decoded;
      }
      tags_seen += result.summary.rejected[static_cast<int>(Stage::kDecode)];
    }
  }
  EXPECT_EQ(decoded, 0);
  // The swapped tags are located and reach Decode, where they are refused.
  EXPECT_GT(tags_seen, 2 * 8 * 28 / 2);
}

}  // namespace
}  // namespace chromatag
