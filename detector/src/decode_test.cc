#include <gtest/gtest.h>

#include <map>
#include <random>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "candidate.h"
#include "chromatag/families/palette.h"
#include "decode.h"
#include "geometry.h"
#include "scratch.h"
#include "stage_switches.h"

namespace chromatag::internal {
namespace {

constexpr int kCellPx = 10;
constexpr int kMarginPx = 20;  // White around the black square.

cv::Scalar Bgr(const Palette& palette, Shade shade) {
  const Rgb8 c = palette.Srgb8(shade);
  return cv::Scalar(c.b, c.g, c.r);
}

// An upright tag of `family` drawn on the pixel grid (cells of `cell_px`),
// its quads where the drawing puts the three borders (pixel centres at
// integers, so an edge lies half a pixel before the cell's first pixel).
// With `swap`, each colour's two shades trade places (a misprinted tag).
cv::Mat DrawTag(const TagFamily& family, int id, bool swap, Candidate* candidate,
                int cell_px = kCellPx) {
  const Palette palette = *BuiltinPalette("default");
  const int cells = family.black_square_cells(), d = family.payload_width();
  const int side = cells * cell_px;
  cv::Mat image(side + 2 * kMarginPx, side + 2 * kMarginPx, CV_8UC3, Bgr(palette, Shade::kWhite));
  cv::rectangle(image, cv::Rect(kMarginPx, kMarginPx, side, side), Bgr(palette, Shade::kBlack),
                cv::FILLED);
  const Code code = family.CodeOf(id);
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      const bool bit = ((code >> (d * d - 1 - (row * d + col))) & 1u) != swap;
      const bool red = family.CellColorAt(row, col) == CellColor::kRed;
      const Shade shade =
          red ? (bit ? Shade::kRed1 : Shade::kRed0) : (bit ? Shade::kGreen1 : Shade::kGreen0);
      cv::rectangle(image,
                    cv::Rect(kMarginPx + (col + 1) * cell_px, kMarginPx + (row + 1) * cell_px,
                             cell_px, cell_px),
                    Bgr(palette, shade), cv::FILLED);
    }
  }
  // The green/black border is one cell inside the black square, the
  // red/green border two (spec section 2).
  for (int ring = 0; ring < kNumRings; ++ring) {
    const int inset = (kBlackWhite - ring) * cell_px;
    const double lo = kMarginPx + inset - 0.5, hi = kMarginPx + side - inset - 0.5;
    candidate->quads[ring] = {cv::Point2d(lo, lo), cv::Point2d(hi, lo), cv::Point2d(hi, hi),
                              cv::Point2d(lo, hi)};
  }
  return image;
}

std::vector<FamilyDecoder> Families(const std::vector<std::string>& names) {
  std::vector<FamilyDecoder> families;
  for (const std::string& name : names) {
    FamilyDecoder entry;
    entry.family = TagFamily::Load(name);
    entry.decoder = CodeDecoder::Create(entry.family, CodeDecoder::DefaultRadius(*entry.family));
    entry.swapped_codes = SwappedCodes(*entry.family);
    entry.oriented_codes = OrientedCodes(*entry.family);
    families.push_back(std::move(entry));
  }
  return families;
}

// Every kept 16h5 ID, drawn upright, decodes as itself, unturned, with no bit
// corrected, its corners the black square's from the top-left on.
TEST(DecodeTest, EveryKept16h5IdReadsAsItself) {
  Scratch scratch;
  const auto families = Families({"16h5", "36h11"});
  const TagFamily& family = *families[0].family;
  for (int id : family.kept_ids()) {
    Candidate candidate;
    const cv::Mat image = DrawTag(family, id, false, &candidate);
    const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
    Detection detection;
    RejectReason why;
    ASSERT_TRUE(
        Decode(view, DetectorOptions{}, families, candidate, &scratch.side_fit, &detection, &why))
        << "ID " << id << ": " << RejectReasonName(why);
    EXPECT_EQ(detection.family, &family);
    EXPECT_EQ(detection.id, id);
    EXPECT_EQ(detection.hamming, 0);
    EXPECT_GE(detection.decision_margin, DetectorOptions{}.min_decision_margin);
    EXPECT_NEAR(detection.corners[0].x, kMarginPx - 0.5, 1e-9);
    EXPECT_NEAR(detection.corners[0].y, kMarginPx - 0.5, 1e-9);
  }
}

// 36h11 tags are told from 16h5 by their ring proportions and decode too.
TEST(DecodeTest, Kept36h11IdsReadAsThemselves) {
  Scratch scratch;
  const auto families = Families({"16h5", "36h11"});
  const TagFamily& family = *families[1].family;
  const std::vector<int>& ids = family.kept_ids();
  for (size_t i = 0; i < ids.size(); i += ids.size() / 25) {
    Candidate candidate;
    const cv::Mat image = DrawTag(family, ids[i], false, &candidate);
    const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
    Detection detection;
    RejectReason why;
    ASSERT_TRUE(
        Decode(view, DetectorOptions{}, families, candidate, &scratch.side_fit, &detection, &why))
        << "ID " << ids[i] << ": " << RejectReasonName(why);
    EXPECT_EQ(detection.family, &family);
    EXPECT_EQ(detection.id, ids[i]);
  }
}

// A tag printed with its shades swapped shows its code's complement; for
// 16h5 several complements lie one or two bits from another ID (14's from
// 25). Sharp and upright, none of them may decode.
TEST(DecodeTest, SwappedShadesNeverDecode) {
  Scratch scratch;
  const auto families = Families({"16h5", "36h11"});
  const TagFamily& family = *families[0].family;
  for (int id : family.kept_ids()) {
    Candidate candidate;
    const cv::Mat image = DrawTag(family, id, true, &candidate);
    const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
    Detection detection;
    RejectReason why;
    EXPECT_FALSE(
        Decode(view, DetectorOptions{}, families, candidate, &scratch.side_fit, &detection, &why))
        << "swapped ID " << id << " read as " << detection.id;
  }
}

// Blur pulls each cell towards its neighbours, and some swapped 16h5 prints
// then read as another ID exactly, with a margin that passes. The blur model
// (kSwappedPrint) must refuse them: none decodes at any blur, and the rule
// is what refuses some of them.
TEST(DecodeTest, BlurredSwappedShadesNeverDecode) {
  Scratch scratch;
  const auto families = Families({"16h5", "36h11"});
  const TagFamily& family = *families[0].family;
  std::map<RejectReason, int> reasons;
  int flagged = 0;  // Reads with fits_swapped_print set.
  for (int id : family.kept_ids()) {
    Candidate candidate;
    const cv::Mat sharp = DrawTag(family, id, true, &candidate);
    for (int trial = 0; trial < 40; ++trial) {
      // Cells of 3 to 5 px, blurred by 0.6 to 1.2 px.
      const double scale = 0.3 + 0.05 * (trial % 5), sigma = 0.6 + 0.15 * (trial / 10);
      cv::Mat image;
      cv::resize(sharp, image, cv::Size(), scale, scale, cv::INTER_AREA);
      Candidate small = candidate;
      for (Quad& quad : small.quads) {
        for (cv::Point2d& p : quad) p = (p + cv::Point2d(0.5, 0.5)) * scale - cv::Point2d(0.5, 0.5);
      }
      cv::GaussianBlur(image, image, cv::Size(), sigma);
      cv::Mat noise(image.size(), CV_16SC3);
      cv::RNG rng(1000 * id + trial);
      rng.fill(noise, cv::RNG::NORMAL, 0, 4);
      image.convertTo(image, CV_16SC3);
      cv::add(image, noise, image);
      image.convertTo(image, CV_8UC3);
      std::vector<uchar> jpeg;
      cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 70});
      image = cv::imdecode(jpeg, cv::IMREAD_COLOR);
      const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
      Detection detection;
      RejectReason why;
      bool fits_swapped_print = false;
      EXPECT_FALSE(Decode(view, DetectorOptions{}, families, small, &scratch.side_fit, &detection,
                          &why, &fits_swapped_print))
          << "swapped ID " << id << " trial " << trial << " read as " << detection.id;
      ++reasons[why];
      // The flag says so whenever a read was refused as a swapped print,
      // also where the reason given is another family's or another rule's.
      if (why == RejectReason::kSwappedPrint) {
        EXPECT_TRUE(fits_swapped_print);
      }
      flagged += fits_swapped_print;
    }
  }
  EXPECT_GT(reasons[RejectReason::kSwappedPrint], 0);
  EXPECT_GE(flagged, reasons[RejectReason::kSwappedPrint]);
}

// Inner rings where neither family puts them: no family fits.
TEST(DecodeTest, RingsOutOfProportionFitNoFamily) {
  Scratch scratch;
  const auto families = Families({"16h5", "36h11"});
  Candidate candidate;
  const cv::Mat image =
      DrawTag(*families[0].family, families[0].family->kept_ids()[0], false, &candidate);
  // The red/green quad shrunk to half its size about the centre.
  const cv::Point2d centre = 0.5 * (candidate.quads[kRedGreen][0] + candidate.quads[kRedGreen][2]);
  for (cv::Point2d& corner : candidate.quads[kRedGreen]) corner = centre + 0.5 * (corner - centre);
  const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
  Detection detection;
  RejectReason why;
  EXPECT_FALSE(
      Decode(view, DetectorOptions{}, families, candidate, &scratch.side_fit, &detection, &why));
  EXPECT_EQ(why, RejectReason::kNoFamilyFits);
}

// Inner quads a little off (as the scans leave them on small tags): Decode
// finds no family whose proportions they fit; DecodeCandidate moves them onto
// their edges and reads the tag. Not with the sub-pixel sides switched off.
TEST(DecodeTest, DecodeCandidateLocatesInnerRingsThatFitNoFamily) {
  Scratch scratch;
  const auto families = Families({"16h5", "36h11"});
  StageSwitches no_sides;
  no_sides.refine_corners = false;
  for (const FamilyDecoder& entry : families) {
    const int id = entry.family->kept_ids()[3];
    Candidate candidate;
    // Cells of 6 px: no family fits beyond 0.35 cells (2.1 px) on average.
    const cv::Mat image = DrawTag(*entry.family, id, false, &candidate, 6);
    for (int ring : {kRedGreen, kGreenBlack}) {
      for (cv::Point2d& corner : candidate.quads[ring]) corner += cv::Point2d(2.0, 2.0);
    }
    const ImageView view(image, PixelOrder::kBgr, ColorTable::Get());
    Detection detection;
    RejectReason why;
    EXPECT_FALSE(
        Decode(view, DetectorOptions{}, families, candidate, &scratch.side_fit, &detection, &why));
    EXPECT_EQ(why, RejectReason::kNoFamilyFits) << entry.family->name();
    Candidate unrefined = candidate;
    EXPECT_FALSE(DecodeCandidate(view, DetectorOptions{}, no_sides, families, &scratch.side_fit,
                                 &unrefined, &detection, &why));
    EXPECT_EQ(why, RejectReason::kNoFamilyFits);
    ASSERT_TRUE(DecodeCandidate(view, DetectorOptions{}, StageSwitches{}, families,
                                &scratch.side_fit, &candidate, &detection, &why))
        << entry.family->name() << ": " << RejectReasonName(why);
    EXPECT_EQ(detection.family, entry.family.get());
    EXPECT_EQ(detection.id, id);
  }
}

// SumCellGrid with each path's kernels (eight points at a time with AVX2)
// gives exactly the scalar sums: grids anywhere in the frame, turned and
// sheared, partly or wholly outside it, and over its last pixel, in either
// channel order.
TEST(SumCellGridTest, MatchesTheScalarSums) {
  cv::Mat image(47, 71, CV_8UC3);
  cv::randu(image, cv::Scalar::all(0), cv::Scalar::all(256));
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> px(-4.0, 75.0), py(-4.0, 51.0), d(-3.0, 3.0);
  int partly_outside = 0, over_last_pixel = 0;
  for (PixelOrder order : {PixelOrder::kBgr, PixelOrder::kRgb}) {
    const ImageView view(image, order, ColorTable::Get());
    const ImageView scalar(image, order, ColorTable::Get(), Kernels::ForPath(KernelPath::kScalar));
    for (int trial = 0; trial < 4000; ++trial) {
      cv::Point2d centre(px(rng), py(rng));
      if (trial % 10 == 0) centre = {70.0 + d(rng) / 3, 46.0 + d(rng) / 3};  // The last pixel.
      const cv::Point2d du(d(rng), d(rng)), dv(d(rng), d(rng));
      const int samples = 2 + trial % 7;
      const PixelSums fast = SumCellGrid(view, centre, du, dv, samples);
      const PixelSums slow = SumCellGrid(scalar, centre, du, dv, samples);
      ASSERT_EQ(fast.n, slow.n) << "trial " << trial;
      ASSERT_EQ(fast.r, slow.r) << "trial " << trial;
      ASSERT_EQ(fast.g, slow.g) << "trial " << trial;
      ASSERT_EQ(fast.b, slow.b) << "trial " << trial;
      partly_outside += slow.n > 0 && slow.n < samples * samples;
      // The grid reaches the frame's last pixel: its colour is in the sums.
      over_last_pixel += trial % 10 == 0 && slow.n > 0;
    }
  }
  EXPECT_GT(partly_outside, 500);
  EXPECT_GT(over_last_pixel, 200);
}

}  // namespace
}  // namespace chromatag::internal
