#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "candidate.h"
#include "initial_scan.h"
#include "scan_rings.h"
#include "scratch.h"
#include "stage_test_support.h"

namespace chromatag::internal {
namespace {

// Tag-like colours, as BGR for cv::Mat.
const cv::Scalar kRed(50, 40, 200), kGreen(70, 160, 40), kBlack(20, 20, 20), kWhite(235, 235, 235),
    kGrey(128, 128, 128);

// Concentric axis-aligned squares about (cx, cy): pixels within half-width 12
// are red, 24 green, 36 black, the rest white. A missing ring is skipped.
constexpr int kRedHalf = 12, kGreenHalf = 24, kBlackHalf = 36;
constexpr int kHalves[kNumRings] = {kRedHalf, kGreenHalf, kBlackHalf};

cv::Mat RenderRings(cv::Size size, int cx, int cy, bool with_green = true, bool with_black = true) {
  return testing::RenderRings(size, cx, cy, {kRedHalf, kGreenHalf, kBlackHalf}, with_green,
                              with_black);
}

// The drawn border between a ring of half-width `half` and the next lies
// half a pixel past its last pixel (pixel centres at integers).
constexpr float EdgeOffset(int half) { return half + 0.5f; }

// InitialScan's four final scans run right, down, left, up, in this order.
const cv::Point2f kAxes[4] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};

// Why InitialScan rejects the seed (a failure is added if it does not).
RejectReason RejectionOf(const cv::Mat& image, cv::Point seed,
                         std::vector<RejectedRegion>* rejected, Seed kind = Seed::kSeed) {
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Scratch scratch;
  Candidate candidate;
  RejectReason why = RejectReason::kPaleRed;
  EXPECT_FALSE(InitialScan(view, DetectorOptions{}, seed, kind, &scratch.ring_scan, &candidate,
                           rejected, &why))
      << "seed " << seed << " accepted";
  return why;
}

// Seeded just inside the red's left edge on the centre row, InitialScan
// converges on the drawn centre and finds each ring's border on each axis.
TEST(InitialScanTest, FindsTheCentreAndTheRingsOfATagLikePattern) {
  Scratch scratch;
  const int cx = 100, cy = 90;
  const cv::Mat image = RenderRings({200, 180}, cx, cy);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Candidate candidate;
  std::vector<RejectedRegion> rejected;
  RejectReason why;
  ASSERT_TRUE(InitialScan(view, DetectorOptions{}, {cx - kRedHalf + 1, cy}, Seed::kSeed,
                          &scratch.ring_scan, &candidate, &rejected, &why))
      << "rejected for " << static_cast<int>(why);
  const cv::Point2f centre(cx, cy);
  EXPECT_LT(cv::norm(candidate.centre - centre), 1.0) << candidate.centre;
  EXPECT_TRUE(candidate.enclosed);
  EXPECT_TRUE(rejected.empty());
  for (int ring = 0; ring < kNumRings; ++ring) {
    ASSERT_EQ(candidate.points[ring].size(), 4u) << "ring " << ring;
    for (int i = 0; i < 4; ++i) {
      const cv::Point2f expected = centre + EdgeOffset(kHalves[ring]) * kAxes[i];
      EXPECT_LT(cv::norm(candidate.points[ring][i] - expected), 1.5)
          << "ring " << ring << " direction " << kAxes[i] << ": " << candidate.points[ring][i];
    }
  }
}

// A dim red (a* 26) seeded in a paler patch two pixels wide at its left edge
// (a* 13.6, as a blurred edge leaves it), in a green ring deep (a* -12) but
// pale (a* -6) below: the drop from the seed into the pale green is 19.5,
// short of a tag's 20, but from the red's peak (sampled in the scan that went
// up through it) 32. InitialScan judges that drop from the peak, checks the
// colours in the tag's own light with the red read at the peak (the patch
// itself is too pale in that light) and finds the tag.
TEST(InitialScanTest, JudgesAShortDropFromTheRedsPeak) {
  const int cx = 100, cy = 90;
  cv::Mat image(180, 200, CV_8UC3, cv::Scalar(235, 235, 235));
  auto square = [&](int half, cv::Scalar bgr) {
    cv::rectangle(image, {cx - half, cy - half}, {cx + half, cy + half}, bgr, cv::FILLED);
  };
  square(kBlackHalf, cv::Scalar(20, 20, 20));
  square(kGreenHalf, cv::Scalar(85, 105, 85));  // Deep green, a* -12.
  cv::rectangle(image, {cx - kGreenHalf, cy + kRedHalf + 1}, {cx + kGreenHalf, cy + kGreenHalf},
                cv::Scalar(90, 100, 90), cv::FILLED);  // Pale green below, a* -6.
  square(kRedHalf, cv::Scalar(60, 60, 120));           // Dim red, a* 26.
  cv::rectangle(image, {cx - kRedHalf, cy - 2}, {cx - kRedHalf + 1, cy + 2},
                cv::Scalar(72, 72, 104), cv::FILLED);  // The pale patch, a* 13.6.
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Scratch scratch;
  Candidate candidate;
  std::vector<RejectedRegion> rejected;
  RejectReason why;
  ASSERT_TRUE(InitialScan(view, DetectorOptions{}, {cx - kRedHalf, cy}, Seed::kSeed,
                          &scratch.ring_scan, &candidate, &rejected, &why))
      << "rejected for " << RejectReasonName(why);
  EXPECT_LT(cv::norm(candidate.centre - cv::Point2f(cx, cy)), 1.5) << candidate.centre;
}

// A seed on grey (a* about 0) is too pale to be a tag's red.
TEST(InitialScanTest, RejectsASeedOnGreyAsPale) {
  cv::Mat image = RenderRings({200, 200}, 100, 100);
  cv::rectangle(image, {160, 20}, {190, 50}, kGrey, cv::FILLED);
  EXPECT_EQ(RejectionOf(image, {175, 35}, nullptr), RejectReason::kPaleRed);
}

// A red square straight on white (a red sign on a wall): with max_green_a
// below white's a* (0), white is far less red than the red but not green, so
// the candidate is dropped at the first scan, before any centring pass, and
// adds no rejected region. With max_green_a above it (the default, 8, which
// keeps thin green rings under a tungsten cast) it gets on to the ring scans.
TEST(InitialScanTest, RejectsRedOnWhiteAtTheFirstScan) {
  Scratch scratch;
  const cv::Mat image = RenderRings({200, 200}, 100, 100, /*with_green=*/false,
                                    /*with_black=*/false);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  const cv::Point seed(100 - kRedHalf + 1, 100);
  DetectorOptions strict;
  strict.max_green_a = -5.0;
  Candidate candidate;
  std::vector<RejectedRegion> rejected;
  RejectReason why;
  ASSERT_FALSE(InitialScan(view, strict, seed, Seed::kSeed, &scratch.ring_scan, &candidate,
                           &rejected, &why));
  EXPECT_EQ(why, RejectReason::kNotGreen);
  EXPECT_TRUE(rejected.empty());
  EXPECT_FALSE(candidate.enclosed);

  ASSERT_FALSE(InitialScan(view, DetectorOptions{}, seed, Seed::kSeed, &scratch.ring_scan,
                           &candidate, &rejected, &why));
  EXPECT_NE(why, RejectReason::kNotGreen);
}

// The red/green border RenderRings draws about (cx, cy), in the eight
// directions of a centring pass.
std::array<cv::Point2f, 8> DrawnRedBorder(int cx, int cy) {
  std::array<cv::Point2f, 8> border;
  const float e = EdgeOffset(kRedHalf);
  const cv::Point2f offsets[8] = {{e, 0},  {e, e},   {0, e},  {-e, e},
                                  {-e, 0}, {-e, -e}, {0, -e}, {e, -e}};
  for (int i = 0; i < 8; ++i) border[i] = cv::Point2f(cx, cy) + offsets[i];
  return border;
}

// A seed inside a region already rejected in this frame is dropped at once,
// even on a tag, and adds no region.
TEST(InitialScanTest, RejectsASeedInARejectedRegion) {
  const int cx = 100, cy = 100;
  const cv::Mat image = RenderRings({200, 200}, cx, cy);
  std::vector<RejectedRegion> rejected = {RejectedRegion::Around(DrawnRedBorder(cx, cy))};
  EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 1, cy}, &rejected),
            RejectReason::kInRejectedRegion);
  EXPECT_EQ(rejected.size(), 1u);
}

// A region the later stages rejected lets its retries through, one seed
// each, then drops seeds as any other; on a tag, the seed that retries
// starts InitialScan, passes it and is marked a retry; a retry that fails
// adds no region.
TEST(InitialScanTest, ARegionWithRetriesLetsThatManySeedsThrough) {
  const int cx = 100, cy = 100;
  const cv::Mat image = RenderRings({200, 200}, cx, cy);
  const std::array<cv::Point2f, 8> border = DrawnRedBorder(cx, cy);
  std::vector<RejectedRegion> rejected = {RejectedRegion::Around(border)};
  rejected[0].retries = 2;
  const cv::Point2f inside(cx, cy), outside(cx + 60, cy);
  int region = -1;
  EXPECT_EQ(AdmitSeed(&rejected, outside, &region), SeedAdmission::kFree);
  EXPECT_EQ(rejected[0].retries, 2);  // Nothing spent outside it.
  EXPECT_EQ(region, -1);
  EXPECT_EQ(AdmitSeed(&rejected, inside), SeedAdmission::kRetry);
  EXPECT_EQ(rejected[0].retries, 1);
  // With a region elsewhere first, the one spent is named by its index.
  std::array<cv::Point2f, 8> elsewhere = border;
  for (cv::Point2f& p : elsewhere) p.x += 100;
  std::vector<RejectedRegion> two = {RejectedRegion::Around(elsewhere), rejected[0]};
  EXPECT_EQ(AdmitSeed(&two, inside, &region), SeedAdmission::kRetry);
  EXPECT_EQ(region, 1);
  EXPECT_EQ(two[1].retries, 0);
  EXPECT_EQ(two[0].retries, 0);  // Untouched: it had none.
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Scratch scratch;
  Candidate candidate;
  RejectReason why = RejectReason::kPaleRed;
  EXPECT_TRUE(InitialScan(view, DetectorOptions{}, {cx - kRedHalf + 1, cy}, Seed::kSeed,
                          &scratch.ring_scan, &candidate, &rejected, &why))
      << RejectReasonName(why);
  EXPECT_TRUE(candidate.retry);
  EXPECT_EQ(candidate.region, 0);  // The region it spent a retry of.
  EXPECT_EQ(rejected[0].retries, 0);
  EXPECT_EQ(AdmitSeed(&rejected, inside), SeedAdmission::kDropped);
  EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 2, cy + 3}, &rejected),
            RejectReason::kInRejectedRegion);
  EXPECT_EQ(AdmitSeed(nullptr, inside), SeedAdmission::kFree);

  // A seed in two regions, one with retries left and one without, is
  // dropped and spends nothing.
  rejected[0].retries = 1;
  rejected.push_back(RejectedRegion::Around(border));
  EXPECT_EQ(AdmitSeed(&rejected, inside), SeedAdmission::kDropped);
  EXPECT_EQ(rejected[0].retries, 1);

  // A retry that fails (red on green without a black ring: the ring scans
  // fail) adds no region; the region's last retry is then spent.
  const cv::Mat no_black =
      RenderRings({200, 200}, cx, cy, /*with_green=*/true, /*with_black=*/false);
  std::vector<RejectedRegion> one = {RejectedRegion::Around(border)};
  one[0].retries = 1;
  EXPECT_EQ(RejectionOf(no_black, {cx - kRedHalf + 1, cy}, &one), RejectReason::kRingScan);
  EXPECT_EQ(one.size(), 1u);
  EXPECT_EQ(RejectionOf(no_black, {cx - kRedHalf + 1, cy}, &one), RejectReason::kInRejectedRegion);
  // Without retries the same failure adds its region.
  std::vector<RejectedRegion> none;
  EXPECT_EQ(RejectionOf(no_black, {cx - kRedHalf + 1, cy}, &none), RejectReason::kRingScan);
  EXPECT_EQ(none.size(), 1u);
}

// A red one pixel tall on green (a speck of a dark frame's chroma noise, or
// a thin red line) is no tag's: dropped after the scans up and down, before
// the other six and without a rejected region. A red five pixels across, in
// a tag's rings, is not.
TEST(InitialScanTest, RejectsARedTooSmallForATag) {
  cv::Mat image(100, 200, CV_8UC3, kGreen);
  cv::rectangle(image, {60, 50}, {140, 50}, kRed, cv::FILLED);
  std::vector<RejectedRegion> rejected;
  EXPECT_EQ(RejectionOf(image, {62, 50}, &rejected), RejectReason::kRedTooSmall);
  EXPECT_TRUE(rejected.empty());

  const cv::Mat small =
      testing::RenderRings({100, 100}, 50, 50, {2, 4, 6}, /*with_green=*/true, /*with_black=*/true);
  const ImageView view(small, PixelOrder::kBgr, ColorTable::Get());
  Scratch scratch;
  Candidate candidate;
  RejectReason why = RejectReason::kPaleRed;
  EXPECT_TRUE(InitialScan(view, DetectorOptions{}, {48, 50}, Seed::kSeed, &scratch.ring_scan,
                          &candidate, &rejected, &why))
      << RejectReasonName(why);
}

// Rows are sampled top to bottom: a region that ends above the row can hold
// no later seed and is forgotten; the others stay.
TEST(InitialScanTest, ForgetsRegionsThatEndAboveTheRow) {
  std::array<cv::Point2f, 8> border;
  std::vector<RejectedRegion> regions;
  for (float top : {10.f, 40.f, 70.f}) {
    for (int i = 0; i < 8; ++i) {
      border[i] = cv::Point2f(50, top + 5) + 5.f * kScanDirections[i];
    }
    regions.push_back(RejectedRegion::Around(border));
  }
  ForgetRegionsAbove(40.f, &regions);
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_TRUE(regions[0].Contains({50, 45}));
  EXPECT_TRUE(regions[1].Contains({50, 75}));
  ForgetRegionsAbove(100.f, &regions);
  EXPECT_TRUE(regions.empty());
}

// Red on green without a black ring fails the first centring pass's ring
// scans (white follows the green); the region then joins `rejected`, around
// the drawn red.
TEST(InitialScanTest, AddsTheRegionRejectedAfterCentring) {
  const int cx = 100, cy = 100;
  const cv::Mat image = RenderRings({200, 200}, cx, cy, /*with_green=*/true, /*with_black=*/false);
  std::vector<RejectedRegion> rejected;
  EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 1, cy}, &rejected), RejectReason::kRingScan);
  ASSERT_EQ(rejected.size(), 1u);
  EXPECT_TRUE(rejected[0].Contains(cv::Point2f(cx, cy)));
  // Rejected by the first centring pass's ring scans, before its centre
  // converged: no retries, and a later seed in the same red is now dropped
  // at once.
  EXPECT_EQ(rejected[0].retries, 0);
  EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 2, cy + 3}, &rejected),
            RejectReason::kInRejectedRegion);
  EXPECT_EQ(rejected.size(), 1u);
}

// A red whose colours passed only in its own light (a seed only a cast or
// dim light explains) leaves no region when it is rejected: those looser
// judgements can lead out of a large red object into a tag beside it. The
// same red seeded as a plain rise does.
TEST(InitialScanTest, ARedJudgedInItsOwnLightAddsNoRegion) {
  const int cx = 100, cy = 100;
  cv::Mat image = RenderRings({200, 200}, cx, cy);
  // White over the black ring's right side: the first pass's ring scan to
  // the right fails; the probe of the seed's own light looks left, from a
  // seed far enough inside the red for a ring scan to start.
  cv::rectangle(image, {cx + kGreenHalf + 1, cy - kBlackHalf}, {cx + kBlackHalf, cy + kBlackHalf},
                kWhite, cv::FILLED);
  for (Seed kind : {Seed::kSeed, Seed::kInACast}) {
    std::vector<RejectedRegion> rejected;
    EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 3, cy}, &rejected, kind),
              RejectReason::kRingScan);
    EXPECT_EQ(rejected.size(), kind == Seed::kSeed ? 1u : 0u)
        << (kind == Seed::kSeed ? "a plain rise" : "a seed in a cast");
  }
}

// After the first centring pass only the rings to the right and below are
// checked; a pattern whose black ring is missing on the left passes those, and
// the final scans, which check all four directions, still reject it.
TEST(InitialScanTest, FinalScansCheckTheDirectionsTheFirstPassSkips) {
  Scratch scratch;
  const int cx = 100, cy = 100;
  cv::Mat image = RenderRings({200, 200}, cx, cy);
  // White over the black ring's left side.
  cv::rectangle(image, {cx - kBlackHalf, cy - kBlackHalf}, {cx - kGreenHalf - 1, cy + kBlackHalf},
                kWhite, cv::FILLED);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  // Each axis scan from the drawn centre: only the one to the left fails.
  for (int i = 0; i < 4; ++i) {
    RingHits hits;
    EXPECT_EQ(ScanRings(view, DetectorOptions{}, cv::Point2f(cx, cy), kAxes[i], view.A(cx, cy),
                        &scratch.ring_scan, &hits),
              i != 2)
        << "direction " << kAxes[i];
  }
  std::vector<RejectedRegion> rejected;
  EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 1, cy}, &rejected), RejectReason::kRingScan);
  EXPECT_EQ(rejected.size(), 1u);
}

// A red rejected after its centre converged (here by the final scans: the
// black ring is missing on the left only) keeps kCentredRedRetries: that
// many later seeds in it run InitialScan again, adding no region, and the
// next is dropped. One rejected before (AddsTheRegionRejectedAfterCentring)
// has none.
TEST(InitialScanTest, ARedRejectedAfterItsCentreConvergedIsRetried) {
  const int cx = 100, cy = 100;
  cv::Mat image = RenderRings({200, 200}, cx, cy);
  cv::rectangle(image, {cx - kBlackHalf, cy - kBlackHalf}, {cx - kGreenHalf - 1, cy + kBlackHalf},
                kWhite, cv::FILLED);
  std::vector<RejectedRegion> rejected;
  EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 1, cy}, &rejected), RejectReason::kRingScan);
  ASSERT_EQ(rejected.size(), 1u);
  EXPECT_EQ(rejected[0].retries, kCentredRedRetries);
  for (int i = 0; i < kCentredRedRetries; ++i) {
    EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 2, cy + 3 + i}, &rejected),
              RejectReason::kRingScan)
        << "retry " << i;
    EXPECT_EQ(rejected.size(), 1u);
  }
  EXPECT_EQ(rejected[0].retries, 0);
  EXPECT_EQ(RejectionOf(image, {cx - kRedHalf + 2, cy - 3}, &rejected),
            RejectReason::kInRejectedRegion);
}

}  // namespace
}  // namespace chromatag::internal
