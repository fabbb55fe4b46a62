// The camera's white balance from the sheet's paper (white_balance.h).
#include "chromatag/calib/white_balance.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "chromatag/calib/thresholds.h"
#include "chromatag/detector/options.h"

namespace chromatag {
namespace {

double Round3(double v) { return std::round(v * 1000.0) / 1000.0; }

// Divided by the largest, rounded to thousandths; the largest is then exactly 1.
WhiteBalanceGains Normalised(const WhiteBalanceGains& gains) {
  const double largest = *std::max_element(gains.begin(), gains.end());
  WhiteBalanceGains out;
  for (int c = 0; c < 3; ++c) out[c] = gains[c] == largest ? 1.0 : Round3(gains[c] / largest);
  return out;
}

// The cast `paper` keeps through `gains`: CIELAB of the balanced white at
// luminance 1 (its L* is 100; a* and b* are the cast).
Lab Residual(const Rgb& paper, const WhiteBalanceGains& gains) {
  const Rgb balanced{gains[0] * paper.r, gains[1] * paper.g, gains[2] * paper.b};
  const double y = LinearRgbToXyz(balanced).Y;
  return XyzToLab(LinearRgbToXyz({balanced.r / y, balanced.g / y, balanced.b / y}));
}

// Each photo's gains, the shared ones and each photo's residual cast through
// them; returns the photo with the largest.
size_t ShareGains(const CalibSheetLayout& layout, const std::vector<PhotoMeasurement>& photos,
                  WhiteBalance* out) {
  // The shared gains: the geometric mean of the photos' (exposure does not
  // matter: each photo's gains are relative to its own largest channel).
  std::vector<Rgb> whites;
  double log_sum[3] = {0, 0, 0};
  for (const PhotoMeasurement& photo : photos) {
    whites.push_back(PaperWhite(layout, photo));
    out->per_photo.push_back(GainsForWhite(whites.back()));
    for (int c = 0; c < 3; ++c) log_sum[c] += std::log(out->per_photo.back()[c]);
  }
  const double n = static_cast<double>(photos.size());
  out->shared =
      Normalised({std::exp(log_sum[0] / n), std::exp(log_sum[1] / n), std::exp(log_sum[2] / n)});
  size_t worst = 0;
  for (size_t i = 0; i < whites.size(); ++i) {
    out->residual.push_back(Residual(whites[i], out->shared));
    const double cast = std::hypot(out->residual[i].a, out->residual[i].b);
    if (cast > out->worst_residual_cast) {
      out->worst_residual_cast = cast;
      worst = i;
    }
  }
  return worst;
}

// Whether the shared gains are written, and why not; `worst` (named
// `name`) is the photo with the largest residual cast.
void Decide(const std::string& name, size_t worst, const WhiteBalanceOptions& options,
            WhiteBalance* out) {
  const WhiteBalanceGains& g = out->shared;
  char text[400];
  if (out->worst_residual_cast > options.max_residual_cast) {
    out->outcome = WhiteBalanceOutcome::kDisagree;
    std::snprintf(text, sizeof(text),
                  "the photos disagree on the light: through their shared gains the paper of %s "
                  "keeps a cast of %.1f (a* %.1f, b* %.1f), more than %.1f",
                  name.c_str(), out->worst_residual_cast, out->residual[worst].a,
                  out->residual[worst].b, options.max_residual_cast);
  } else if (*std::min_element(g.begin(), g.end()) < kMinWhiteBalanceGain) {
    out->outcome = WhiteBalanceOutcome::kTooStrong;
    std::snprintf(text, sizeof(text),
                  "the cast is too strong to balance: gains %.3f, %.3f, %.3f, below the "
                  "detector's %.1f",
                  g[0], g[1], g[2], kMinWhiteBalanceGain);
  } else if (out->finding_margin_balanced < out->finding_margin_as_shot) {
    // The gains only darken: they take the picture down to the level of its
    // weakest channel, and a light that gave the reds a* loses it again.
    out->outcome = WhiteBalanceOutcome::kNotNeeded;
    std::snprintf(text, sizeof(text),
                  "not needed: this light takes no a* from the reds (finding margin %.1f as "
                  "shot, %.1f through the gains %.3f, %.3f, %.3f)",
                  out->finding_margin_as_shot, out->finding_margin_balanced, g[0], g[1], g[2]);
  } else {
    out->outcome = WhiteBalanceOutcome::kWritten;
    out->gains = g;
    return;
  }
  out->why = text;
}

}  // namespace

bool WhiteBalanceOptions::IsValid(std::string* error) const {
  if (!(max_residual_cast > 0 && max_residual_cast <= 50)) {
    if (error) *error = "the white balance's tolerance (residual cast) must be in (0, 50]";
    return false;
  }
  return true;
}

WhiteBalanceGains GainsForWhite(const Rgb& paper) {
  return Normalised({1.0 / paper.r, 1.0 / paper.g, 1.0 / paper.b});
}

Rgb PaperWhite(const CalibSheetLayout& layout, const PhotoMeasurement& photo) {
  Rgb sum{0, 0, 0};
  int n = 0;
  for (const Patch& patch : layout.patches) {
    const PatchMeasurement& m = photo.patches[patch.index];
    if (patch.kind != PatchKind::kPaper || !m.usable()) continue;
    sum.r += SrgbToLinear(m.camera_rgb.r);
    sum.g += SrgbToLinear(m.camera_rgb.g);
    sum.b += SrgbToLinear(m.camera_rgb.b);
    ++n;
  }
  // MeasurePhoto refuses a photo with fewer than 4 usable paper patches.
  // A channel at 0 (light of one colour) keeps a floor, so its gain is
  // finite (and refused as too strong).
  if (n == 0) return {1, 1, 1};
  return {std::max(sum.r / n, 1e-4), std::max(sum.g / n, 1e-4), std::max(sum.b / n, 1e-4)};
}

double FindingMargin(const CalibSheetLayout& layout, const PhotoMeasurement& photo,
                     const WhiteBalanceGains& gains) {
  const auto shades = ReadShades(layout, photo, gains);
  const Margins m = MarginsOf({shades[0], shades[1], shades[2], shades[3]},
                              shades[static_cast<int>(Shade::kWhite)].seen.L, /*seen=*/true);
  return std::min(m.a_gap, m.min_red_a - kMinTagRedA);
}

WhiteBalance MeasureWhiteBalance(const CalibSheetLayout& layout,
                                 const std::vector<PhotoMeasurement>& photos,
                                 const std::vector<std::string>& names,
                                 const WhiteBalanceOptions& options) {
  WhiteBalance out;
  if (photos.empty()) return out;
  const size_t worst = ShareGains(layout, photos, &out);
  out.finding_margin_as_shot = out.finding_margin_balanced = 1e300;
  for (const PhotoMeasurement& photo : photos) {
    out.finding_margin_as_shot =
        std::min(out.finding_margin_as_shot, FindingMargin(layout, photo, {1.0, 1.0, 1.0}));
    out.finding_margin_balanced =
        std::min(out.finding_margin_balanced, FindingMargin(layout, photo, out.shared));
  }
  Decide(worst < names.size() ? names[worst] : "a photo", worst, options, &out);
  return out;
}

Lab SeenThrough(const Rgb& camera_rgb, const WhiteBalanceGains& gains) {
  return XyzToLab(
      LinearRgbToXyz({gains[0] * SrgbToLinear(camera_rgb.r), gains[1] * SrgbToLinear(camera_rgb.g),
                      gains[2] * SrgbToLinear(camera_rgb.b)}));
}

}  // namespace chromatag
