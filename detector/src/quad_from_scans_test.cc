#include <gtest/gtest.h>

#include "build_polygon.h"
#include "candidate.h"
#include "geometry.h"
#include "initial_scan.h"
#include "poly_to_quad.h"
#include "quad_from_scans.h"
#include "refine_corners.h"
#include "scratch.h"
#include "stage_switches.h"
#include "stage_test_support.h"

namespace chromatag::internal {
namespace {

using testing::kTestBlack;
using testing::kTestGreen;
using testing::kTestRed;
using testing::kTestWhite;
using testing::NearestCorner;
using testing::RotatedSquare;

// The rings' outlines: half-sides of red 12.5, green 24.5 and black 36.5 px.
constexpr double kOutlineHalf[kNumRings] = {12.5, 24.5, 36.5};

// The three rings' quads filled with tag-like colours on white, antialiased,
// in a 200 x 200 frame.
cv::Mat RenderRingQuads(const std::array<Quad, kNumRings>& rings) {
  return testing::RenderQuadsAntialiased({200, 200}, {rings.begin(), rings.end()},
                                         {kTestRed, kTestGreen, kTestBlack}, kTestWhite);
}

// The largest distance from a corner of `truth` to the matching corner of
// `quad` (both clockwise; only the first corner may differ).
double MaxCornerDistance(const Quad& quad, const Quad& truth) {
  const int shift = NearestCorner(quad, truth[0]);
  double worst = 0;
  for (int i = 0; i < 4; ++i) worst = std::max(worst, cv::norm(quad[(i + shift) % 4] - truth[i]));
  return worst;
}

// Turned by 22.5 degrees, the eight scans meet each side twice and no
// corner: the eight points then lie on two squares alike, the drawn one and
// the one through the chords that cut its corners (about 9 px off at its
// corners on the outer ring). The edge directions pick the drawn one at every
// turn, and the sub-pixel sides then land within 0.25 px.
TEST(QuadsFromScansTest, GivesEachRingsDrawnQuadAtAnyTurn) {
  Scratch scratch;
  const cv::Point2d centre(100.3, 99.6);
  for (double degrees : {0.0, 10.0, 22.5, 30.0, 45.0, 67.5, 80.0}) {
    std::array<Quad, kNumRings> truth;
    for (int ring = 0; ring < kNumRings; ++ring)
      truth[ring] = RotatedSquare(centre, kOutlineHalf[ring], degrees);
    const cv::Mat image = RenderRingQuads(truth);
    const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
    Candidate candidate;
    RejectReason why;
    ASSERT_TRUE(InitialScan(view, DetectorOptions{}, {95, 100}, Seed::kSeed, &scratch.ring_scan,
                            &candidate, nullptr, &why))
        << degrees << " degrees: " << RejectReasonName(why);
    const auto points_before = candidate.points;
    ASSERT_TRUE(QuadsFromScans(view, DetectorOptions{}, &scratch.ring_scan, &candidate))
        << degrees << " degrees";
    // Only the quads are written: BuildPolygon could still start from here.
    EXPECT_EQ(candidate.points, points_before);
    for (int ring = 0; ring < kNumRings; ++ring) {
      EXPECT_LT(MaxCornerDistance(candidate.quads[ring], truth[ring]), 1.5)
          << degrees << " degrees, ring " << ring;
    }
    ASSERT_TRUE(NestedAndRefined(view, StageSwitches{}, &scratch.side_fit, &candidate, &why))
        << degrees << " degrees: " << RejectReasonName(why);
    EXPECT_LT(MaxCornerDistance(candidate.quads[kBlackWhite], truth[kBlackWhite]), 0.25)
        << degrees << " degrees, after the outer sub-pixel sides";
    // The inner quads stay as the scans left them until asked for.
    ASSERT_TRUE(RefineInnerQuads(view, &scratch.side_fit, &candidate)) << degrees << " degrees";
    for (int ring = 0; ring < kNumRings; ++ring) {
      EXPECT_LT(MaxCornerDistance(candidate.quads[ring], truth[ring]), 0.25)
          << degrees << " degrees, ring " << ring << " after the sub-pixel sides";
    }
  }
}

// Under perspective a side can fall between two scans: with three sides
// met, there is no quad to give, and BuildPolygon takes over.
TEST(QuadsFromScansTest, DeclinesWhenAScanMissesASide) {
  Scratch scratch;
  const cv::Point2d centre(100.3, 99.6);
  // A quad whose short upper side (seen from the centre between 80 and 50
  // degrees anticlockwise of "right") lies between the up and the up-right
  // scans.
  auto kite = [&](double radius) {
    Quad quad;
    const double degrees[4] = {-80.0, -50.0, 90.0, 180.0};
    for (int i = 0; i < 4; ++i) {
      const double a = degrees[i] * CV_PI / 180;
      quad[i] = centre + radius * cv::Point2d(std::cos(a), std::sin(a));
    }
    return quad;
  };
  const std::array<Quad, kNumRings> truth = {kite(14.0), kite(27.0), kite(40.0)};
  ASSERT_TRUE(IsConvexClockwise(truth[kBlackWhite]));
  const cv::Mat image = RenderRingQuads(truth);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Candidate candidate;
  RejectReason why;
  ASSERT_TRUE(InitialScan(view, DetectorOptions{}, {100, 100}, Seed::kSeed, &scratch.ring_scan,
                          &candidate, nullptr, &why))
      << RejectReasonName(why);
  EXPECT_FALSE(QuadsFromScans(view, DetectorOptions{}, &scratch.ring_scan, &candidate));
}

// It starts from InitialScan's four axis scans and nothing else.
TEST(QuadsFromScansTest, NeedsExactlyInitialScansFourScans) {
  Scratch scratch;
  const cv::Mat image = testing::RenderRings({200, 200}, 100, 100, {12, 24, 36});
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Candidate candidate;
  RejectReason why;
  ASSERT_TRUE(InitialScan(view, DetectorOptions{}, {95, 100}, Seed::kSeed, &scratch.ring_scan,
                          &candidate, nullptr, &why));
  ASSERT_TRUE(BuildPolygon(view, DetectorOptions{}, &scratch.ring_scan, &scratch.polygon,
                           &candidate, &why));
  ASSERT_GT(candidate.points[kBlackWhite].size(), 4u);
  EXPECT_FALSE(QuadsFromScans(view, DetectorOptions{}, &scratch.ring_scan, &candidate));
}

}  // namespace
}  // namespace chromatag::internal
