// The detector on frames made the way a colour camera makes them:
// light, optics blur and sensor noise act on linear values, an RGGB mosaic is
// demosaiced, the sRGB curve is followed by the camera's own tone curve, and
// JPEG subsamples the chroma 4:2:0. Each test is one failure mode the
// camera-like benchmark showed: dim cards, steep views, JPEG at quality 60,
// demosaicing, and small 36h11 tags. Every tag must be found once with its
// ID and corners within a pixel (or 1.5 px where blur and the view allow no
// better), and nothing else may be found.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "chromatag/detector/detector.h"
#include "chromatag/families/family.h"
#include "expect_detections.h"
#include "synthetic_scene.h"

namespace chromatag {
namespace {

using testing::BothFamiliesDetector;
using testing::Demosaic;
using testing::ExpectEveryTagFoundOnce;
using testing::RenderScene;
using testing::SceneOptions;
using testing::SceneTag;

// A camera with a neutral white balance, mild blur and noise in linear light.
SceneOptions Camera(unsigned seed) {
  SceneOptions options;
  options.linear_camera = true;
  options.blur_sigma = 0.7;
  options.noise_sigma = 0.8;
  options.shot_noise = 0.01;
  options.seed = seed;
  return options;
}

// `count` tags of `family_name` (kept IDs spread over the family), `size` px,
// turned by assorted angles and tilted by `tilt_deg` about assorted axes, in
// a grid of `columns` with a pitch that leaves room for the tilted outline.
std::vector<SceneTag> Tags(const std::string& family_name, int count, double size, double tilt_deg,
                           int columns, double print_chroma, SceneOptions* options) {
  const auto family = TagFamily::Load(family_name);
  const std::vector<int>& ids = family->kept_ids();
  const double pitch = std::ceil(size * 1.9);
  std::vector<SceneTag> tags;
  for (int i = 0; i < count; ++i) {
    SceneTag tag;
    tag.family = family_name;
    tag.id = ids[static_cast<size_t>(i) * ids.size() / count];  // Distinct IDs.
    tag.black_square_px = size;
    tag.centre = {pitch * (0.5 + i % columns) + 0.3, pitch * (0.5 + i / columns) - 0.2};
    tag.rotation_deg = 11 + 37 * i;
    tag.tilt_deg = tilt_deg;
    tag.tilt_axis_deg = 23 + 61 * i;
    tag.print_chroma = print_chroma;
    tags.push_back(tag);
  }
  options->width = static_cast<int>(pitch * columns);
  options->height = static_cast<int>(pitch * ((count + columns - 1) / columns));
  return tags;
}

// A card at half exposure under a flattening tone curve: the red, the green
// and the black ring crowd together at low lightness, and the a* jump is a
// third smaller than in a well-exposed frame.
TEST(DetectorCameraTest, DimCards) {
  auto detector = BothFamiliesDetector();
  for (const std::string family : {"16h5", "36h11"}) {
    for (double exposure : {0.5, 0.65}) {
      SceneOptions options = Camera(7);
      const std::vector<SceneTag> tags = Tags(family, 8, 48, 40, 4, 0.75, &options);
      options.exposure = exposure;
      options.tone_gamma = 1.3;
      options.gain = {0.95, 1.0, 1.05};
      ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 1.0,
                              family + " exposure " + std::to_string(exposure));
    }
  }
}

// Views of 62-72 degrees: the tag is foreshortened three-fold along one axis,
// so scans in fixed directions cross the rings at grazing angles and a
// blurred ring's width changes along its length.
TEST(DetectorCameraTest, SteepViews) {
  auto detector = BothFamiliesDetector();
  for (const std::string family : {"16h5", "36h11"}) {
    for (double tilt : {62.0, 67.0, 72.0}) {
      SceneOptions options = Camera(11);
      const std::vector<SceneTag> tags = Tags(family, 6, 110, tilt, 3, 0.9, &options);
      ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 1.5,
                              family + " tilt " + std::to_string(tilt));
    }
  }
}

// Views of 68-72 degrees from close by (the camera 2.5 tag sizes away): the
// far end of the tag is half the size of the near end, so each ring is half
// as wide at one end of a side as at the other, and a search that takes one
// cell size per side reads the quiet zone as the black ring.
TEST(DetectorCameraTest, SteepCloseViews) {
  auto detector = BothFamiliesDetector();
  for (const std::string family : {"16h5", "36h11"}) {
    for (double tilt : {68.0, 72.0}) {
      SceneOptions options = Camera(29);
      std::vector<SceneTag> tags = Tags(family, 6, 120, tilt, 3, 0.9, &options);
      for (SceneTag& tag : tags) tag.distance = 2.5;
      ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 1.5,
                              family + " close, tilt " + std::to_string(tilt));
    }
  }
}

// JPEG at quality 60 with OpenCV's 4:2:0 chroma: the chroma is halved in
// resolution and blocky, so a thin green ring is smeared into its neighbours.
TEST(DetectorCameraTest, JpegQuality60) {
  auto detector = BothFamiliesDetector();
  for (const std::string family : {"16h5", "36h11"}) {
    for (double size : {50.0, 80.0}) {
      SceneOptions options = Camera(13);
      const std::vector<SceneTag> tags = Tags(family, 8, size, 25, 4, 0.85, &options);
      options.jpeg_quality = 60;
      ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 1.0,
                              family + " JPEG q60 size " + std::to_string(size));
    }
  }
}

// An RGGB mosaic demosaiced bilinearly and edge-aware: colour fringes along
// every black/white edge and chroma blurred over two pixels.
TEST(DetectorCameraTest, DemosaicedFrames) {
  auto detector = BothFamiliesDetector();
  for (const std::string family : {"16h5", "36h11"}) {
    for (Demosaic demosaic : {Demosaic::kBilinear, Demosaic::kEdgeAware}) {
      SceneOptions options = Camera(17);
      const std::vector<SceneTag> tags = Tags(family, 8, 42, 45, 4, 0.85, &options);
      options.demosaic = demosaic;
      ExpectEveryTagFoundOnce(
          *detector, RenderScene(tags, options), 1.5,
          family + (demosaic == Demosaic::kBilinear ? " bilinear" : " edge-aware"));
    }
  }
}

// 36h11 black squares of 36-44 px: cells of 4.5-5.5 px, the red centre's
// cells as small as 16h5's at 27-33 px.
TEST(DetectorCameraTest, Small36h11Tags) {
  auto detector = BothFamiliesDetector();
  for (double size : {36.0, 44.0}) {
    SceneOptions options = Camera(19);
    const std::vector<SceneTag> tags = Tags("36h11", 12, size, 20, 6, 0.9, &options);
    ExpectEveryTagFoundOnce(*detector, RenderScene(tags, options), 1.0,
                            "36h11 size " + std::to_string(size));
  }
}

// 36h11 tags of 34 px under blur of 1.3 px (and edge-aware demosaicing):
// each 4 px cell takes a large share of its neighbours' shade, and reads miss
// the code unless Decode takes that share out again.
TEST(DetectorCameraTest, BlurredSmall36h11Tags) {
  auto detector = BothFamiliesDetector();
  for (Demosaic demosaic : {Demosaic::kNone, Demosaic::kEdgeAware}) {
    SceneOptions options = Camera(23);
    const std::vector<SceneTag> tags = Tags("36h11", 12, 34, 20, 6, 0.9, &options);
    options.blur_sigma = 1.3;
    options.demosaic = demosaic;
    ExpectEveryTagFoundOnce(
        *detector, RenderScene(tags, options), 1.5,
        std::string("36h11 size 34 blur 1.3") + (demosaic == Demosaic::kNone ? "" : " edge-aware"));
  }
}

// Small 16h5 tags under blur and JPEG's 4:2:0 chroma: cells next to the
// other shade are pulled towards the split, and the decision margin of the
// right reads falls below the gate (2 of 14 tags lost before). Decode keeps
// a read whose code explains every cell under its model of blur.
TEST(DetectorCameraTest, BlurredSmall16h5TagsInJpeg) {
  auto detector = BothFamiliesDetector();
  const struct { double size, blur; } conditions[] = {{34, 1.0}, {34, 1.15}};
  for (const auto& c : conditions) {
    SceneOptions options = Camera(29);
    const std::vector<SceneTag> tags = Tags("16h5", 14, c.size, 20, 7, 0.9, &options);
    options.blur_sigma = c.blur;
    options.jpeg_quality = 65;
    ExpectEveryTagFoundOnce(
        *detector, RenderScene(tags, options), 1.5,
        "16h5 size " + std::to_string(c.size) + " blur " + std::to_string(c.blur) + " JPEG 65");
  }
}

}  // namespace
}  // namespace chromatag
