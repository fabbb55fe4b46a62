#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "chromatag/families/color.h"
#include "geometry.h"
#include "poly_to_quad.h"
#include "refine_corners.h"
#include "scratch.h"
#include "stage_test_support.h"

namespace chromatag::internal {
namespace {

using testing::NearestCorner;
using testing::RotatedSquare;

// A black quad on white, antialiased: point-sampled at 8x, then averaged
// down. Coordinates as ImageView::Sample reads them (pixel centres at
// integers), so the high-resolution pixel X has its centre at (X + 0.5) / 8 - 0.5.
cv::Mat RenderQuad(cv::Size size, const Quad& quad) {
  return testing::RenderQuadsAntialiased(size, {quad}, {cv::Vec3b(0, 0, 0)},
                                         cv::Vec3b(255, 255, 255));
}

// Expects `fitted` to be `truth` up to which corner comes first.
void ExpectSameQuad(const Quad& fitted, const Quad& truth, double tolerance) {
  const int shift = NearestCorner(fitted, truth[0]);
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d& p = fitted[(i + shift) % 4];
    EXPECT_NEAR(p.x, truth[i].x, tolerance) << "corner " << i;
    EXPECT_NEAR(p.y, truth[i].y, tolerance) << "corner " << i;
  }
}

// Points along each side, both ends included, every `spacing` pixels.
std::vector<cv::Point2f> AlongSides(const Quad& quad, double spacing) {
  std::vector<cv::Point2f> points;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d p = quad[i], q = quad[(i + 1) % 4];
    const int n = static_cast<int>(std::ceil(cv::norm(q - p) / spacing));
    for (int j = 0; j < n; ++j) points.emplace_back(p + (q - p) * (static_cast<double>(j) / n));
  }
  return points;
}

// FitQuad on exact points along a convex quad's sides, with interior points
// mixed in, returns the quad's corners, clockwise.
TEST(FitQuadTest, RecoversTheCornersOfAConvexQuad) {
  Scratch scratch;
  const Quad truth = {{{20.25, 10.5}, {90, 18}, {82.75, 70}, {15, 60.5}}};
  ASSERT_TRUE(IsConvexClockwise(truth));
  std::vector<cv::Point2f> points = AlongSides(truth, 3.0);
  for (cv::Point2f inner : {cv::Point2f(50, 40), cv::Point2f(30, 30), cv::Point2f(70, 55)})
    points.insert(points.begin() + points.size() / 2, inner);
  Quad fitted;
  ASSERT_TRUE(FitQuad(points, &scratch.quad_fit, &fitted));
  EXPECT_TRUE(IsConvexClockwise(fitted));
  ExpectSameQuad(fitted, truth, 1e-3);
}

// Points a little off the sides (at most 0.2 px along the normal) still give
// corners within a fraction of a pixel.
TEST(FitQuadTest, ToleratesNoisyPoints) {
  Scratch scratch;
  const Quad truth = RotatedSquare({60, 50}, 25, 25);
  cv::RNG rng(3);
  std::vector<cv::Point2f> points;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d p = truth[i], q = truth[(i + 1) % 4];
    const cv::Point2d along = (q - p) / cv::norm(q - p), normal(-along.y, along.x);
    for (double t = 0.0; t < 1.0; t += 0.04) {
      points.emplace_back(p + t * (q - p) + rng.uniform(-0.2, 0.2) * normal);
    }
  }
  Quad fitted;
  ASSERT_TRUE(FitQuad(points, &scratch.quad_fit, &fitted));
  ExpectSameQuad(fitted, truth, 0.5);
}

// Fewer than four points cannot make a quad; neither can points on a line.
TEST(FitQuadTest, FailsOnTooFewPoints) {
  Scratch scratch;
  Quad quad;
  EXPECT_FALSE(FitQuad({}, &scratch.quad_fit, &quad));
  EXPECT_FALSE(FitQuad({{0, 0}, {10, 0}, {5, 8}}, &scratch.quad_fit, &quad));
  EXPECT_FALSE(FitQuad({{0, 0}, {1, 1}, {2, 2}, {3, 3}, {4, 4}}, &scratch.quad_fit, &quad));
}

// The side search for the outer border: black inside, white outside.
SideSearch BlackOnWhite(double cell) {
  return {kGray, kRisesOutwards, kMinGrayContrast, cell, 20, 4.0};
}

// A quad 1.5 px off moves onto an antialiased black square, axis-aligned or
// turned, to within 0.1 px of its corners.
TEST(RefineQuadTest, MovesOntoTheEdgesOfABlackSquare) {
  Scratch scratch;
  for (double degrees : {0.0, 17.0, 40.0}) {
    const Quad truth = RotatedSquare({60.3, 59.6}, 28.0, degrees);
    const cv::Mat image = RenderQuad({120, 120}, truth);
    const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
    const cv::Point2d offsets[4] = {{1.5, 0}, {0, -1.5}, {-1.06, 1.06}, {1.06, 1.06}};
    Quad quad;
    for (int i = 0; i < 4; ++i) quad[i] = truth[i] + offsets[i];
    ASSERT_TRUE(RefineQuad(view, BlackOnWhite(56.0 / 8), &scratch.side_fit, &quad))
        << degrees << " degrees";
    for (int i = 0; i < 4; ++i) {
      EXPECT_LT(cv::norm(quad[i] - truth[i]), 0.1) << degrees << " degrees, corner " << i;
    }
  }
}

// `sharp` blurred by `blur` px in linear light then sRGB-encoded, as a
// camera makes it (`lens`), or blurred in its encoded values, as software
// resizing does.
cv::Mat Blurred(const cv::Mat& sharp, bool lens, double blur) {
  cv::Mat f;
  sharp.convertTo(f, CV_32FC3, 1.0 / 255);
  const auto each = [&f](double (*curve)(double)) {
    f.forEach<cv::Vec3f>([curve](cv::Vec3f& p, const int*) {
      for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(curve(p[c]));
    });
  };
  if (lens) each(&SrgbToLinear);
  cv::GaussianBlur(f, f, cv::Size(0, 0), blur);
  if (lens) each(&LinearToSrgb);
  cv::Mat image;
  f.convertTo(image, CV_8UC3, 255.0);
  return image;
}

// A tag's black ring (1 of `cells` cells) with green inside it and white
// outside: `truth` is its outer quad, the green quad is it inset by a cell
// in the tag's plane; Blurred.
cv::Mat RenderRing(const Quad& truth, int cells, bool lens, double blur) {
  const Quad green = InsetSquare(UnitSquareToQuad(truth), 1.0 / cells);
  return Blurred(testing::RenderQuadsAntialiased({120, 120}, {green, truth},
                                                 {cv::Vec3b(60, 150, 70), cv::Vec3b(5, 5, 5)},
                                                 cv::Vec3b(230, 230, 230)),
                 lens, blur);
}

// The mean of the four corners' offsets outwards from the quad's centre,
// px: negative for a square found too small.
double MeanOutwards(const Quad& found, const Quad& truth) {
  const cv::Point2d centre = 0.25 * (truth[0] + truth[1] + truth[2] + truth[3]);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d outwards = truth[i] - centre;
    sum += (found[NearestCorner(found, truth[i])] - truth[i]).dot(outwards) / cv::norm(outwards);
  }
  return 0.25 * sum;
}

// Where an image was blurred decides where its edges lie between their
// levels. A tag's black ring (1 of 6 cells of 8 px) blurred by 1.5 px either
// way: RefineReportedQuad places the black square within 0.15 px in both,
// while the encoded average alone finds the camera's about 0.9 px too small.
TEST(RefineQuadTest, ReportedCornersFollowWhereTheImageWasBlurred) {
  Scratch scratch;
  for (bool lens : {true, false}) {
    for (double degrees : {0.0, 23.0}) {
      const std::string what =
          std::string(lens ? "lens" : "software") + ", " + std::to_string(degrees) + " degrees";
      const cv::Point2d centre(60.3, 59.6);
      const Quad truth = RotatedSquare(centre, 48.0, degrees);
      const ImageView view(RenderRing(truth, 6, lens, 1.5), PixelOrder::kBgr, ColorTable::Get());
      Quad encoded = truth;
      ASSERT_TRUE(RefineQuad(view, BlackOnWhite(8.0), &scratch.side_fit, &encoded)) << what;
      Quad reported = encoded;  // As the stages leave it.
      cv::Matx<double, 8, 8> covariance;
      ASSERT_TRUE(RefineReportedQuad(view, 6, &scratch.side_fit, &reported, &covariance)) << what;
      // Above the floor, below 0.6 px per coordinate on a clean edge, and
      // the corners' errors within three of its standard deviations.
      for (int i = 0; i < 8; ++i) {
        EXPECT_GE(covariance(i, i), kCornerNoise.floor_px * kCornerNoise.floor_px) << what;
        EXPECT_LT(covariance(i, i), 0.36) << what;
        const cv::Point2d error = reported[i / 2] - truth[i / 2];
        EXPECT_LT(std::abs(i % 2 == 0 ? error.x : error.y), 3.0 * std::sqrt(covariance(i, i)))
            << what;
      }
      for (int i = 0; i < 4; ++i) {
        EXPECT_LT(cv::norm(reported[i] - truth[i]), 0.15) << what << ", corner " << i;
        // Each corner sqrt(2) x 0.8 px nearer the centre, give or take.
        if (lens) {
          EXPECT_LT(cv::norm(encoded[i] - centre), cv::norm(truth[i] - centre) - 0.8) << i;
        }
      }
    }
  }
}

// A small tag under a heavy blur: cells of 4 px, a lens blur of 1.5 and 2
// px. The ring's middle never reaches black, so its own share would put the
// corners of the 2 px blur 1.1 px inside the square; the reported square is
// the camera's, its corners within 0.35 px outwards or inwards. The same
// ring blurred in software is reported too large (its corners up to 1.8 px
// outwards), as ResolvedShare says.
TEST(RefineQuadTest, AnUnresolvedRingTakesACamerasBlur) {
  Scratch scratch;
  for (double blur : {1.5, 2.0}) {
    for (bool lens : {true, false}) {
      const std::string what =
          std::string(lens ? "lens" : "software") + " blur " + std::to_string(blur);
      const Quad truth = RotatedSquare({60.3, 59.6}, 24.0, 17.0);
      const ImageView view(RenderRing(truth, 6, lens, blur), PixelOrder::kBgr, ColorTable::Get());
      Quad reported = truth;
      ASSERT_TRUE(RefineQuad(view, BlackOnWhite(4.0), &scratch.side_fit, &reported)) << what;
      ASSERT_TRUE(RefineReportedQuad(view, 6, &scratch.side_fit, &reported)) << what;
      const double outwards = MeanOutwards(reported, truth);
      if (lens) {
        EXPECT_LT(std::abs(outwards), 0.35) << what;
      } else {
        EXPECT_GT(outwards, 0.5) << what;
        EXPECT_LT(outwards, 2.0) << what;
      }
    }
  }
}

// A near tag seen steeply: its far half is much smaller than its near half,
// so the ring's inner square is not 4/6 of the outer one's side. With the
// ring's own proportion under that perspective, the lens-blurred ring puts
// the black square within 0.15 px.
TEST(RefineQuadTest, ReportedCornersHoldUnderStrongPerspective) {
  Scratch scratch;
  const Quad truth = {{{22.0, 30.0}, {98.0, 22.0}, {104.0, 100.0}, {28.0, 84.0}}};
  ASSERT_TRUE(IsConvexClockwise(truth));
  const ImageView view(RenderRing(truth, 6, true, 1.0), PixelOrder::kBgr, ColorTable::Get());
  Quad reported = truth;
  ASSERT_TRUE(RefineQuad(view, BlackOnWhite(10.0), &scratch.side_fit, &reported));
  ASSERT_TRUE(RefineReportedQuad(view, 6, &scratch.side_fit, &reported));
  for (int i = 0; i < 4; ++i)
    EXPECT_LT(cv::norm(reported[NearestCorner(reported, truth[i])] - truth[i]), 0.15) << i;
}

// A black square on white has no inner border: the ring cannot tell the
// blurs apart, and the corners are the camera's (linear light). Each
// pixel's share of white is its light (black 0, white 1), blurred by the
// lens, then sRGB-encoded.
TEST(RefineQuadTest, ABorderWithoutRingIsReportedAsACameraSeesIt) {
  Scratch scratch;
  const Quad truth = RotatedSquare({60.3, 59.6}, 48.0, 11.0);
  cv::Mat light;
  RenderQuad({120, 120}, truth).convertTo(light, CV_32FC3, 1.0 / 255);
  cv::GaussianBlur(light, light, cv::Size(0, 0), 1.5);
  light.forEach<cv::Vec3f>([](cv::Vec3f& p, const int*) {
    for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(LinearToSrgb(p[c]));
  });
  cv::Mat image;
  light.convertTo(image, CV_8UC3, 255.0);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Quad reported = truth;
  ASSERT_TRUE(RefineQuad(view, BlackOnWhite(8.0), &scratch.side_fit, &reported));
  ASSERT_TRUE(RefineReportedQuad(view, 6, &scratch.side_fit, &reported));
  EXPECT_LT(std::abs(MeanOutwards(reported, truth)), 0.1);
}

// The ring's own share where it is resolved, a camera's (1) where it is not,
// linear between.
TEST(RefineQuadTest, ResolvedShareTrustsTheRingAsFarAsItIsResolved) {
  const double spread = 0.5;
  EXPECT_DOUBLE_EQ(ResolvedShare(0.2, kResolvedRingCells * spread, spread), 0.2);
  EXPECT_DOUBLE_EQ(ResolvedShare(0.2, 30 * spread, spread), 0.2);
  EXPECT_DOUBLE_EQ(ResolvedShare(0.2, kUnresolvedRingCells * spread, spread), 1.0);
  EXPECT_DOUBLE_EQ(ResolvedShare(0.2, 2 * spread, spread), 1.0);
  const double middle = 0.5 * (kUnresolvedRingCells + kResolvedRingCells);
  EXPECT_NEAR(ResolvedShare(0.2, middle * spread, spread), 0.6, 1e-12);
  // No spread (the two conventions agree): nothing to tell apart.
  EXPECT_DOUBLE_EQ(ResolvedShare(0.2, 4.0, 0.0), 0.2);
}

// Each side's offset error moves the two corners it ends at together along
// its normal; its angle error moves them apart, in proportion to their
// distance from its middle.
TEST(CornerCovarianceTest, CarriesEachSidesErrorsToTheCornersItEndsAt) {
  const Quad square = {cv::Point2d(0, 0), cv::Point2d(10, 0), cv::Point2d(10, 10),
                       cv::Point2d(0, 10)};
  std::array<SideFit, 4> sides;
  const double offset[4] = {0.01, 0.04, 0.09, 0.16};
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d p = square[i], q = square[(i + 1) % 4];
    sides[i].line = {0.5 * (p + q), (q - p) / cv::norm(q - p)};
    sides[i].offset_variance = offset[i];
  }
  sides[0].angle_variance = 0.0004;  // 0.01 px^2 at 5 px from its middle.
  const cv::Matx<double, 8, 8> c = CornerCovariance(sides, square);
  // Corner 0 (on sides 3 and 0): x from the left side, y from the top.
  EXPECT_NEAR(c(0, 0), 0.16, 1e-12);
  EXPECT_NEAR(c(1, 1), 0.01 + 0.01, 1e-12);
  // Corner 1 (on sides 0 and 1): x from the right side, y from the top.
  EXPECT_NEAR(c(2, 2), 0.04, 1e-12);
  EXPECT_NEAR(c(3, 3), 0.02, 1e-12);
  // The top side's two ends: the offset together, the angle apart.
  EXPECT_NEAR(c(1, 3), 0.01 - 0.01, 1e-12);
  // Corners on no common side are independent.
  EXPECT_NEAR(c(0, 4), 0.0, 1e-12);
  EXPECT_NEAR(c(1, 5), 0.0, 1e-12);
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) EXPECT_NEAR(c(i, j), c(j, i), 1e-12);
  }
}

// Without an edge (a flat frame), or with the edge the wrong way round (a
// white square on black), the quad is left as it was.
TEST(RefineQuadTest, FailsAndLeavesTheQuadWithoutAMatchingEdge) {
  Scratch scratch;
  const Quad start = RotatedSquare({60, 60}, 28.0, 10.0);
  const cv::Mat flat(120, 120, CV_8UC3, cv::Scalar::all(128));
  const cv::Mat inverted = ~RenderQuad({120, 120}, start);
  for (const cv::Mat* image : {&flat, &inverted}) {
    const ImageView view(*image, PixelOrder::kBgr, ColorTable::Get());
    Quad quad = start;
    EXPECT_FALSE(RefineQuad(view, BlackOnWhite(7.0), &scratch.side_fit, &quad));
    EXPECT_EQ(quad, start);
  }
}

// EdgePoints (eight profiles at a time with AVX2 where it can) finds exactly
// what EdgePoint finds profile by profile: the same edge points to the last
// bit, the same failures, for both edge channels, both polarities and both
// halfway levels (Halfway), with
// profiles of different lengths side by side, and near and across every
// border of the frame, including its last pixel.
TEST(EdgePointsTest, MatchesEdgePointProfileByProfile) {
  // Coloured quads on a noisy background, so that the profiles meet real
  // edges (gray and red - green) as well as noise and nothing.
  const Quad outer = RotatedSquare({40.3, 31.7}, 34.0, 23.0);
  const Quad inner = RotatedSquare({40.3, 31.7}, 18.0, 23.0);
  cv::Mat image = testing::RenderQuadsAntialiased({83, 61}, {outer, inner},
                                                  {cv::Vec3b(20, 30, 25), cv::Vec3b(40, 60, 200)},
                                                  cv::Vec3b(235, 240, 230));
  // Without noise as well: flat plateaus give equal changes, and the first
  // of equals must win in both.
  cv::Mat noisy = image.clone(), noise(image.size(), CV_8UC3);
  cv::randn(noise, cv::Scalar::all(0), cv::Scalar::all(6));
  noisy += noise;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> px(-3.0, 86.0), py(-3.0, 64.0), angle(0.0, 2 * CV_PI),
      half(0.6, 4.4), offset(0.5, 5.0);
  int found = 0, compared = 0;
  for (const cv::Mat* frame : {&image, &noisy}) {
    for (PixelOrder order : {PixelOrder::kBgr, PixelOrder::kRgb}) {
      const ImageView view(*frame, order, ColorTable::Get());
      for (int trial = 0; trial < 2000; ++trial) {
        // Each profile in its own direction, as a quad's four sides are
        // read in one batch.
        const int count = 1 + trial % 20;
        std::vector<ProfileSpec> spec(count);
        for (ProfileSpec& s : spec) {
          const double a = angle(rng);
          s = {{px(rng), py(rng)}, {std::cos(a), std::sin(a)}, half(rng), offset(rng)};
        }
        for (const ChannelWeights& channel : {kGray, kRedMinusGreen}) {
          for (int polarity : {kRisesOutwards, kFallsOutwards}) {
            for (Halfway halfway : {Halfway::kEncoded, Halfway::kLinearLight}) {
              std::vector<ProfileEdge> out(count);
              EdgePoints(view, channel, polarity, spec.data(), count, 12.f, out.data(), halfway);
              for (int j = 0; j < count; ++j) {
                cv::Point2d edge;
                const bool ok = EdgePoint(view, channel, polarity, spec[j], 12.f, &edge, halfway);
                ASSERT_EQ(out[j].found, ok) << "trial " << trial << " profile " << j;
                ++compared;
                if (!ok) continue;
                ++found;
                ASSERT_EQ(out[j].edge.x, edge.x) << "trial " << trial << " profile " << j;
                ASSERT_EQ(out[j].edge.y, edge.y) << "trial " << trial << " profile " << j;
              }
            }
          }
        }
      }
    }
  }
  // Both outcomes were compared thousands of times (about 15,000 edge
  // points found of 340,000 profiles).
  EXPECT_GT(found, 5000);
  EXPECT_GT(compared - found, 5000);
}

}  // namespace
}  // namespace chromatag::internal
