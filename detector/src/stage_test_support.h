// Drawn patterns for the stages' unit tests (detector/src/*_test.cc): tag-like
// rings with known borders, axis-aligned or turned, hard-edged or
// antialiased; and the first stages run on them. Test-only.
#ifndef CHROMATAG_DETECTOR_SRC_STAGE_TEST_SUPPORT_H_
#define CHROMATAG_DETECTOR_SRC_STAGE_TEST_SUPPORT_H_

#include <array>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "build_polygon.h"
#include "candidate.h"
#include "geometry.h"
#include "initial_scan.h"
#include "scratch.h"

namespace chromatag::internal::testing {

// Tag-like colours, BGR as in a cv::Mat.
inline const cv::Vec3b kTestRed(50, 40, 200), kTestGreen(70, 160, 40), kTestBlack(20, 20, 20),
    kTestWhite(235, 235, 235);

// The square of half-side `half` about `centre`, turned `degrees` clockwise
// on screen; corners clockwise from the (unturned) top-left.
inline Quad RotatedSquare(cv::Point2d centre, double half, double degrees) {
  const double c = std::cos(degrees * CV_PI / 180), s = std::sin(degrees * CV_PI / 180);
  const cv::Point2d offsets[4] = {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
  Quad quad;
  for (int i = 0; i < 4; ++i) {
    quad[i] = centre +
              cv::Point2d(c * offsets[i].x - s * offsets[i].y, s * offsets[i].x + c * offsets[i].y);
  }
  return quad;
}

// Whether p lies inside the clockwise convex quad.
inline bool InsideQuad(const Quad& quad, cv::Point2d p) {
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d u = quad[(i + 1) % 4] - quad[i], v = p - quad[i];
    if (u.x * v.y - u.y * v.x < 0) return false;
  }
  return true;
}

// Quads filled with their colours (the first that holds a point wins) on
// `background`, antialiased: point-sampled at 8x, then averaged down.
// Coordinates as ImageView::Sample reads them (pixel centres at integers), so
// the high-resolution pixel X has its centre at (X + 0.5) / 8 - 0.5.
inline cv::Mat RenderQuadsAntialiased(cv::Size size, const std::vector<Quad>& quads,
                                      const std::vector<cv::Vec3b>& colours, cv::Vec3b background) {
  constexpr int kScale = 8;
  cv::Mat fine(size * kScale, CV_8UC3, cv::Scalar(background[0], background[1], background[2]));
  for (int y = 0; y < fine.rows; ++y) {
    for (int x = 0; x < fine.cols; ++x) {
      const cv::Point2d p((x + 0.5) / kScale - 0.5, (y + 0.5) / kScale - 0.5);
      for (size_t q = 0; q < quads.size(); ++q) {
        if (InsideQuad(quads[q], p)) {
          fine.at<cv::Vec3b>(y, x) = colours[q];
          break;
        }
      }
    }
  }
  cv::Mat image;
  cv::resize(fine, image, size, 0, 0, cv::INTER_AREA);
  return image;
}

// Concentric axis-aligned filled squares about (cx, cy), hard-edged: pixels
// within half-width halves[kRedGreen] are red, halves[kGreenBlack] green,
// halves[kBlackWhite] black, the rest white. A ring left out is not drawn.
inline cv::Mat RenderRings(cv::Size size, int cx, int cy, const std::array<int, kNumRings>& halves,
                           bool with_green = true, bool with_black = true) {
  cv::Mat image(size, CV_8UC3, cv::Scalar(kTestWhite[0], kTestWhite[1], kTestWhite[2]));
  auto square = [&](int half, cv::Vec3b colour) {
    cv::rectangle(image, {cx - half, cy - half}, {cx + half, cy + half},
                  cv::Scalar(colour[0], colour[1], colour[2]), cv::FILLED);
  };
  if (with_black) square(halves[kBlackWhite], kTestBlack);
  if (with_green) square(halves[kGreenBlack], kTestGreen);
  square(halves[kRedGreen], kTestRed);
  return image;
}

// The index of the corner of `quad` nearest to `p`.
inline int NearestCorner(const Quad& quad, cv::Point2d p) {
  int best = 0;
  for (int i = 1; i < 4; ++i) {
    if (cv::norm(quad[i] - p) < cv::norm(quad[best] - p)) best = i;
  }
  return best;
}

// InitialScan then BuildPolygon from `seed` with the default options, as
// Detect runs them; a failure names the stage and its reason.
inline ::testing::AssertionResult ScanAndBuildPolygon(const ImageView& view, cv::Point seed,
                                                      Candidate* candidate) {
  Scratch scratch;
  RejectReason why;
  if (!InitialScan(view, DetectorOptions{}, seed, Seed::kSeed, &scratch.ring_scan, candidate,
                   nullptr, &why))
    return ::testing::AssertionFailure() << "InitialScan rejected: " << RejectReasonName(why);
  if (!BuildPolygon(view, DetectorOptions{}, &scratch.ring_scan, &scratch.polygon, candidate, &why))
    return ::testing::AssertionFailure() << "BuildPolygon rejected: " << RejectReasonName(why);
  return ::testing::AssertionSuccess();
}

}  // namespace chromatag::internal::testing

#endif  // CHROMATAG_DETECTOR_SRC_STAGE_TEST_SUPPORT_H_
