// Measuring a photo of the calibration sheet (measure.h): locate, sample,
// fit the paper white across the sheet, normalise, flag, check exposure.
#include "chromatag/calib/measure.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "sample_patch.h"

namespace chromatag {
namespace {

// The paper white as a smooth field over the page: per linear channel, a
// quadratic in page position (affine with few paper patches). Light from a
// lamp or a window falls off across an A4 sheet by 10-30 %; a single white
// would turn that into a lightness error of several L* units.
class WhiteField {
 public:
  bool Fit(const std::vector<std::array<double, 2>>& positions, const std::vector<Rgb>& whites,
           const PageSize& page) {
    half_w_ = page.width_mm / 2;
    half_h_ = page.height_mm / 2;
    terms_ = positions.size() >= 10 ? 6 : 3;
    if (positions.size() < 4) return false;
    cv::Mat a(static_cast<int>(positions.size()), terms_, CV_64F);
    cv::Mat rhs(static_cast<int>(positions.size()), 3, CV_64F);
    for (size_t i = 0; i < positions.size(); ++i) {
      const auto basis = Basis(positions[i]);
      for (int j = 0; j < terms_; ++j) a.at<double>(static_cast<int>(i), j) = basis[j];
      rhs.at<double>(static_cast<int>(i), 0) = whites[i].r;
      rhs.at<double>(static_cast<int>(i), 1) = whites[i].g;
      rhs.at<double>(static_cast<int>(i), 2) = whites[i].b;
    }
    return cv::solve(a, rhs, coefficients_, cv::DECOMP_SVD);
  }

  Rgb At(const std::array<double, 2>& mm) const {
    const auto basis = Basis(mm);
    double v[3] = {0, 0, 0};
    for (int c = 0; c < 3; ++c) {
      for (int j = 0; j < terms_; ++j) v[c] += basis[j] * coefficients_.at<double>(j, c);
      v[c] = std::max(v[c], 1e-4);
    }
    return {v[0], v[1], v[2]};
  }

 private:
  std::array<double, 6> Basis(const std::array<double, 2>& mm) const {
    const double u = mm[0] / half_w_ - 1, v = mm[1] / half_h_ - 1;
    return {1, u, v, u * u, u * v, v * v};
  }
  double half_w_ = 1, half_h_ = 1;
  int terms_ = 6;
  cv::Mat coefficients_;
};

double Luminance(const Rgb& linear) { return LinearRgbToXyz(linear).Y; }

Lab Normalised(const Rgb& linear, const Rgb& white) {
  return XyzToLab(LinearRgbToXyz({linear.r / white.r, linear.g / white.g, linear.b / white.b}));
}

uint32_t LocalFlags(const internal::PatchPixels& px, const MeasureOptions& options) {
  uint32_t flags = 0;
  if (px.pixels < options.min_pixels) return kFlagTooSmall;
  if (px.clipped_high > options.max_clipped_fraction || px.clipped_zero > 0.25)
    flags |= kFlagClipped;
  return flags;
}

// Fits the white through the usable paper patches, twice: the second time
// without those the first fit shows brighter than their neighbours (glare).
bool FitWhite(const CalibSheetLayout& layout, const std::vector<internal::PatchPixels>& pixels,
              const MeasureOptions& options, std::vector<PatchMeasurement>* patches,
              WhiteField* field) {
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<std::array<double, 2>> positions;
    std::vector<Rgb> whites;
    for (const Patch& patch : layout.patches) {
      if (patch.kind != PatchKind::kPaper || (*patches)[patch.index].flags) continue;
      positions.push_back(patch.CenterMm());
      whites.push_back(pixels[patch.index].linear_mean);
    }
    if (!field->Fit(positions, whites, layout.page)) return false;
    if (pass == 1) break;
    for (const Patch& patch : layout.patches) {
      if (patch.kind != PatchKind::kPaper || (*patches)[patch.index].flags) continue;
      const double fitted = Luminance(field->At(patch.CenterMm()));
      const double seen = Luminance(pixels[patch.index].linear_mean);
      if (seen > fitted * (1 + options.max_white_residual))
        (*patches)[patch.index].flags |= kFlagGlare;
    }
  }
  return true;
}

std::string Fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return message;
}

// Samples every patch and records what is known before the white: as shot, local flags.
std::vector<internal::PatchPixels> SamplePatches(const cv::Mat& bgr, const SheetLocation& location,
                                                 const CalibSheetLayout& layout,
                                                 const MeasureOptions& options,
                                                 std::vector<PatchMeasurement>* patches) {
  std::vector<internal::PatchPixels> pixels;
  for (const Patch& patch : layout.patches) {
    pixels.push_back(internal::SamplePatch(bgr, location.image_from_page, patch, options));
    PatchMeasurement m;
    m.index = patch.index;
    m.pixels = pixels.back().pixels;
    m.flags = LocalFlags(pixels.back(), options);
    m.noise_a = pixels.back().noise_a;
    m.noise_b = pixels.back().noise_b;
    const Rgb& lin = pixels.back().linear_mean;
    m.camera_rgb = {LinearToSrgb(lin.r), LinearToSrgb(lin.g), LinearToSrgb(lin.b)};
    m.as_shot = XyzToLab(LinearRgbToXyz(lin));
    patches->push_back(m);
  }
  return pixels;
}

// Refuses (false, *error) a photo with the paper clipped in half or more of the paper patches.
bool CheckNotOverexposed(const CalibSheetLayout& layout,
                         const std::vector<PatchMeasurement>& patches, std::string* error) {
  int paper = 0, paper_clipped = 0;
  for (const Patch& patch : layout.patches) {
    if (patch.kind != PatchKind::kPaper) continue;
    ++paper;
    paper_clipped += (patches[patch.index].flags & kFlagClipped) != 0;
  }
  if (paper_clipped * 2 >= paper) {
    Fail(error, "overexposed: the paper white is clipped (255) in " +
                    std::to_string(paper_clipped) + " of " + std::to_string(paper) +
                    " white patches; lower the exposure until the paper is light grey to white "
                    "without clipping");
    return false;
  }
  return true;
}

// The exposure: the median over the usable paper patches of their brightest channel, 8-bit.
double WhiteLevel(const CalibSheetLayout& layout, const std::vector<PatchMeasurement>& patches) {
  std::vector<double> levels;
  for (const Patch& patch : layout.patches) {
    if (patch.kind != PatchKind::kPaper || patches[patch.index].flags) continue;
    const Rgb& c = patches[patch.index].camera_rgb;
    levels.push_back(255.0 * std::max({c.r, c.g, c.b}));
  }
  std::nth_element(levels.begin(), levels.begin() + levels.size() / 2, levels.end());
  return levels[levels.size() / 2];
}

// Refuses (false, *error) a white level below options.min_white_level.
bool CheckNotUnderexposed(double white_level, const MeasureOptions& options, std::string* error) {
  if (white_level < options.min_white_level) {
    char text[200];
    std::snprintf(text, sizeof(text),
                  "underexposed: the paper white reads only %.0f of 255 (at least %d needed); add "
                  "light or raise the exposure",
                  white_level, options.min_white_level);
    Fail(error, text);
    return false;
  }
  return true;
}

// Normalise, then the flags that need the white: glare and blur.
void NormaliseAndFlag(const CalibSheetLayout& layout,
                      const std::vector<internal::PatchPixels>& pixels, const WhiteField& field,
                      const MeasureOptions& options, std::vector<PatchMeasurement>* patches) {
  for (const Patch& patch : layout.patches) {
    PatchMeasurement& m = (*patches)[patch.index];
    const internal::PatchPixels& px = pixels[patch.index];
    const Rgb white = field.At(patch.CenterMm());
    m.lab = Normalised(px.linear_mean, white);
    if (!(m.flags & kFlagTooSmall)) {
      const double tail = px.y_p98 - px.y_p50;
      if (tail > options.glare_tail * Luminance(white) && tail > 3 * (px.y_p50 - px.y_p02))
        m.flags |= kFlagGlare;
      if (Ciede2000(m.lab, Normalised(px.inner_linear_mean, white)) > options.max_inner_delta_e)
        m.flags |= kFlagBlurred;
    }
  }
}

// The colour (not paper) patches: how many, how many flagged and for what, usable per shade.
struct FlagTally {
  int colour = 0;
  int flagged = 0;
  int counts[4] = {0, 0, 0, 0};                // Per flag bit: clipped, glare, blurred, too small.
  std::array<int, kNumShades> usable_shade{};  // Palette patches only.
};

// Tallies the colour patches' flags and the usable palette patches of each shade.
FlagTally TallyFlags(const CalibSheetLayout& layout, const std::vector<PatchMeasurement>& patches) {
  FlagTally tally;
  for (const Patch& patch : layout.patches) {
    if (patch.kind == PatchKind::kPaper) continue;
    const PatchMeasurement& m = patches[patch.index];
    ++tally.colour;
    if (!m.usable()) {
      ++tally.flagged;
      for (int bit = 0; bit < 4; ++bit) tally.counts[bit] += (m.flags >> bit) & 1;
    } else if (patch.kind == PatchKind::kPalette) {
      ++tally.usable_shade[static_cast<int>(patch.shade)];
    }
  }
  return tally;
}

// Refuses (false, *error) too many flagged colour patches, or a shade with no usable patch.
bool CheckEnoughUsable(const FlagTally& tally, const MeasureOptions& options, std::string* error) {
  const int* counts = tally.counts;
  if (tally.flagged > options.max_flagged_fraction * tally.colour) {
    char text[320];
    std::snprintf(text, sizeof(text),
                  "%d of %d colour patches are unusable (clipped %d, glare %d, blurred %d, too "
                  "small %d): retake the photo %s",
                  tally.flagged, tally.colour, counts[0], counts[1], counts[2], counts[3],
                  counts[3] > counts[2] ? "closer to the sheet"
                  : counts[1] > 0       ? "without glare (light from the side, not behind you)"
                  : counts[0] > 0       ? "with a lower exposure"
                                        : "in focus and without motion");
    Fail(error, text);
    return false;
  }
  for (Shade shade : {Shade::kRed1, Shade::kRed0, Shade::kGreen1, Shade::kGreen0, Shade::kBlack}) {
    if (tally.usable_shade[static_cast<int>(shade)] == 0) {
      Fail(error, std::string("no usable patch of ") + ShadeName(shade) +
                      " (all flagged): retake the photo");
      return false;
    }
  }
  return true;
}

}  // namespace

bool MeasureOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(central_fraction > 0 && central_fraction < 1))
    return fail("central_fraction must be in (0, 1)");
  if (!(inner_fraction > 0 && inner_fraction < central_fraction))
    return fail("inner_fraction must be in (0, central_fraction)");
  if (!(trim >= 0 && trim <= 0.45)) return fail("trim must be in [0, 0.45]");
  if (min_pixels < 4) return fail("min_pixels must be at least 4");
  if (!(max_flagged_fraction > 0 && max_flagged_fraction <= 1))
    return fail("max_flagged_fraction must be in (0, 1]");
  if (!(max_inner_delta_e > 0 && glare_tail > 0 && max_white_residual > 0 &&
        max_clipped_fraction >= 0))
    return fail("flag thresholds must be positive");
  if (min_white_level < 1 || min_white_level > 250)
    return fail("min_white_level must be in [1, 250]");
  return true;
}

std::string FlagNames(uint32_t flags) {
  std::string out;
  const std::pair<uint32_t, const char*> names[] = {{kFlagClipped, "clipped"},
                                                    {kFlagGlare, "glare"},
                                                    {kFlagBlurred, "blurred"},
                                                    {kFlagTooSmall, "too-small"}};
  for (const auto& [bit, name] : names) {
    if (flags & bit) out += (out.empty() ? "" : ", ") + std::string(name);
  }
  return out;
}

std::optional<PhotoMeasurement> MeasurePhoto(const cv::Mat& bgr, const CalibSheetLayout& layout,
                                             const MeasureOptions& options,
                                             const LocateOptions& locate, std::string* error) {
  if (!options.IsValid(error)) return std::nullopt;
  PhotoMeasurement out;
  const auto location = LocateSheet(bgr, layout, locate, error);
  if (!location) return std::nullopt;
  out.location = *location;

  const std::vector<internal::PatchPixels> pixels =
      SamplePatches(bgr, *location, layout, options, &out.patches);
  if (!CheckNotOverexposed(layout, out.patches, error)) return std::nullopt;
  WhiteField field;
  if (!FitWhite(layout, pixels, options, &out.patches, &field)) {
    Fail(error,
         "too few usable paper-white patches to know the white (need 4): retake the photo "
         "without glare or shadows");
    return std::nullopt;
  }
  out.white_level = WhiteLevel(layout, out.patches);
  if (!CheckNotUnderexposed(out.white_level, options, error)) return std::nullopt;

  NormaliseAndFlag(layout, pixels, field, options, &out.patches);
  const FlagTally tally = TallyFlags(layout, out.patches);
  out.flagged = tally.flagged;
  if (!CheckEnoughUsable(tally, options, error)) return std::nullopt;
  return out;
}

}  // namespace chromatag
