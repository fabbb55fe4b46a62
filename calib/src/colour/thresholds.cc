// Margins and derived detector thresholds (thresholds.h).
#include "chromatag/calib/thresholds.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "chromatag/calib/white_balance.h"

namespace chromatag {
namespace {

std::string Format(const char* format, double a, double b = 0, double c = 0) {
  char text[400];
  std::snprintf(text, sizeof(text), format, a, b, c);
  return text;
}

// The derived detector options, unrounded; warns when BorderThresh has too little room.
DetectorOptions DeriveOptions(const Margins& w, const ThresholdOptions& o,
                              std::vector<std::string>* warnings) {
  const double s = o.safety_factor;
  DetectorOptions d;
  const double dim_gap = w.a_gap * std::cbrt(o.dimmest_light) / s;
  d.adiff_thresh = std::clamp(dim_gap, o.min_adiff, o.max_adiff);
  // The rises over two samples (DetectorOptions::two_step_rises) stay on
  // whatever the print: they find borders that the camera blurred, which
  // no photo of the sheet can promise away.
  d.two_step_rises = true;
  // BorderThresh must stay above the a* step between two shades of one
  // colour (with the safety factor) plus twice the pixel noise (the scan
  // needs M pixels in a row past it, so rarer noise does not count), or the
  // scan stops inside the red; and
  // below the red-green gap and the quiet zone's L* lead (or it never sees
  // the border). The upper bound wins: a scan that never leaves the red
  // finds nothing at all.
  const double need = s * w.a_spread + 2.0 * w.noise_a;
  const double room = std::max(o.min_border, std::min(w.a_gap, w.l_gap_white) / s);
  // Never above the detector's default: the ring scans' own floors (a third
  // of the red's a*, 0.3 of the green's L*) already keep them past a shade
  // step, and a higher one loses dim and small tags (a derived 19.7 found 3
  // fewer of the camera set's 288 default-press tags from 30 px).
  d.border_thresh = std::clamp(
      need, o.min_border, std::max(o.min_border, std::min(room, DetectorOptions{}.border_thresh)));
  if (need > room) {
    warnings->push_back(Format(
        "BorderThresh: the two shades of a colour differ by %.1f in a* (noise %.1f), too close "
        "to the red-green gap of %.1f: scans may stop at a shade change",
        w.a_spread, w.noise_a, w.a_gap));
    warnings->back() += Format("; BorderThresh set to %.1f (wanted %.1f)", d.border_thresh, need);
  }
  d.min_decision_margin =
      std::clamp(w.decision() / s, o.min_decision_margin, o.max_decision_margin);
  // A tag's green ring, one cell wide, reads redder through blur and JPEG's
  // chroma than a patch of it: past the red, the detector meets the greens'
  // a* plus a share of the red-green gap. Never below the default, which
  // allows for that on the benchmark's casts.
  d.max_green_a = std::clamp(w.max_green_a + w.a_gap / (2.0 * s), DetectorOptions{}.max_green_a,
                             kMaxGreenALimit);
  return d;
}

// The verdict on the red-green a* gap, which ADiffThresh (unrounded) seeds on.
PairVerdict AGapVerdict(const Margins& w, double adiff_thresh, const ThresholdOptions& o) {
  const double s = o.safety_factor;
  PairVerdict a_pair{"reds / greens (a*)", w.a_gap, Verdict::kGood, ""};
  if (w.a_gap / s < o.min_adiff) {
    a_pair.verdict = Verdict::kFail;
    a_pair.why =
        Format("a* gap %.1f: too small to seed on with a safety factor of %.1f", w.a_gap, s);
  } else if (w.min_red_a < kMinTagRedA + 2) {
    a_pair.verdict = Verdict::kFail;
    a_pair.why = Format(
        "the reds print at a* %.1f, at the detector's floor of %.0f for a red: "
        "tags in dimmer or cooler light will not be found",
        w.min_red_a, kMinTagRedA);
  } else if (w.a_gap / s < o.thin_adiff) {
    a_pair.verdict = Verdict::kThin;
    a_pair.why = Format(
        "ADiffThresh %.1f is below %.1f, where natural scenes begin to seed "
        "candidates: expect more false candidates (slower, not wrong)",
        w.a_gap / s, o.thin_adiff);
  } else {
    a_pair.why = Format("ADiffThresh %.1f", adiff_thresh);
  }
  return a_pair;
}

// The verdict on one colour's b* gap between its shades and its expected decision margin.
PairVerdict BGapVerdict(const char* name, double gap, double decision, const ThresholdOptions& o) {
  const double s = o.safety_factor;
  PairVerdict v{name, gap, Verdict::kGood, ""};
  if (gap <= 0) {
    v.verdict = Verdict::kFail;
    v.why = Format(
        "the shades print in the wrong b* order (gap %.1f): tags decode as wrong "
        "IDs; use the calibrated palette",
        gap);
  } else if (decision < s * o.min_decision_margin) {
    v.verdict = Verdict::kFail;
    v.why = Format(
        "b* gap %.1f, expected decision margin %.1f: below %.1f, decoding is a coin "
        "toss",
        gap, decision, s * o.min_decision_margin);
  } else if (gap < o.thin_b_gap || decision < o.thin_decision) {
    v.verdict = Verdict::kThin;
    v.why = Format(
        "b* gap %.1f, expected decision margin %.1f: decodes, but blur or a cast "
        "will cost IDs",
        gap, decision);
  } else {
    v.why = Format("b* gap %.1f, expected decision margin %.1f", gap, decision);
  }
  return v;
}

// Rounds the derived options to tenths.
void RoundToTenths(DetectorOptions* d) {
  // Tenths: finer than any of this is measured, and readable in the file.
  for (double* v : {&d->adiff_thresh, &d->border_thresh, &d->min_decision_margin, &d->max_green_a})
    *v = std::round(*v * 10.0) / 10.0;
}

}  // namespace

bool ThresholdOptions::IsValid(std::string* error) const {
  if (!(safety_factor >= 1 && safety_factor <= 10)) {
    if (error) *error = "safety factor must be in [1, 10]";
    return false;
  }
  if (!(dimmest_light > 0 && dimmest_light <= 1)) {
    if (error) *error = "dimmest light must be in (0, 1] (a share of the photos' light)";
    return false;
  }
  if (!(min_adiff > 0 && max_adiff >= min_adiff && max_adiff <= 200 && min_border > 0 &&
        min_border <= 100 && min_decision_margin >= 0 &&
        max_decision_margin >= min_decision_margin)) {
    if (error) *error = "threshold bounds must be positive and ordered";
    return false;
  }
  return true;
}

const char* VerdictName(Verdict verdict) {
  switch (verdict) {
    case Verdict::kGood:
      return "good";
    case Verdict::kThin:
      return "thin";
    case Verdict::kFail:
      return "fail";
  }
  return "?";
}

std::array<ShadeReading, kNumShades> ReadShades(const CalibSheetLayout& layout,
                                                const PhotoMeasurement& photo,
                                                const std::array<double, 3>& white_balance) {
  std::array<ShadeReading, kNumShades> out{};
  std::array<std::vector<const PatchMeasurement*>, kNumShades> members;
  for (const Patch& patch : layout.patches) {
    const PatchMeasurement& m = photo.patches[patch.index];
    if (!m.usable()) continue;
    if (patch.kind == PatchKind::kPalette) members[static_cast<int>(patch.shade)].push_back(&m);
    if (patch.kind == PatchKind::kPaper) members[static_cast<int>(Shade::kWhite)].push_back(&m);
  }
  for (int s = 0; s < kNumShades; ++s) {
    ShadeReading& r = out[s];
    r.count = static_cast<int>(members[s].size());
    if (r.count == 0) continue;
    for (const PatchMeasurement* m : members[s]) {
      const Lab seen = SeenThrough(m->camera_rgb, white_balance);
      r.seen.L += seen.L / r.count;
      r.seen.a += seen.a / r.count;
      r.seen.b += seen.b / r.count;
      r.lab.L += m->lab.L / r.count;
      r.lab.a += m->lab.a / r.count;
      r.lab.b += m->lab.b / r.count;
      r.as_shot.L += m->as_shot.L / r.count;
      r.as_shot.a += m->as_shot.a / r.count;
      r.as_shot.b += m->as_shot.b / r.count;
      r.pixel_noise_a = std::max(r.pixel_noise_a, m->noise_a);
      r.pixel_noise_b = std::max(r.pixel_noise_b, m->noise_b);
    }
    double sq = 0;
    for (const PatchMeasurement* m : members[s]) sq += std::pow(m->lab.b - r.lab.b, 2);
    r.repeat_spread_b = r.count > 1 ? std::sqrt(sq / (r.count - 1)) : 0.0;
  }
  return out;
}

DerivedThresholds DeriveThresholds(const std::vector<Margins>& per_photo_worst,
                                   const ThresholdOptions& o) {
  DerivedThresholds out;
  if (per_photo_worst.empty()) return out;
  Margins w = per_photo_worst[0];
  for (const Margins& m : per_photo_worst) w = Worst(w, m);
  out.worst = w;
  out.options = DeriveOptions(w, o, &out.warnings);
  out.verdicts.push_back(AGapVerdict(w, out.options.adiff_thresh, o));
  out.verdicts.push_back(BGapVerdict("red-1 / red-0 (b*)", w.red_b_gap, w.red_decision, o));
  out.verdicts.push_back(BGapVerdict("green-1 / green-0 (b*)", w.green_b_gap, w.green_decision, o));
  RoundToTenths(&out.options);
  for (const PairVerdict& v : out.verdicts) {
    if (v.verdict != Verdict::kGood)
      out.warnings.push_back(v.pair + " " + VerdictName(v.verdict) + ": " + v.why);
  }
  return out;
}

}  // namespace chromatag
