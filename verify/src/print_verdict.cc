// The print check's verdicts (print_verdict.h). A tag's shades are judged
// against the detector's own thresholds (ADiffThresh, max_green_a, the
// family's decision margin) and warn below the calibration's "thin" ones.
#include "print_verdict.h"

#include <algorithm>
#include <cmath>

#include "chromatag/detector/options.h"
#include "chromatag/families/palette.h"
#include "print_internal.h"

namespace chromatag::internal {
namespace {

void JudgeBGap(const char* colour, Shade one, Shade zero, double gap, double decision,
               const PrintedShades& c, const Palette& palette, double need,
               const PrintCheckOptions& o, std::vector<Finding>* findings) {
  const double b1 = c.shades[static_cast<int>(one)].lab.b;
  const double b0 = c.shades[static_cast<int>(zero)].lab.b;
  const double design =
      palette.lab[static_cast<int>(one)].b - palette.lab[static_cast<int>(zero)].b;
  // A split under half a thin one either way that does not decode is no
  // order at all: the shades print alike (a swapped print's split is the
  // design's, the other way). One that decodes is only thin.
  if (std::abs(gap) < o.thin_b_gap / 2 && (gap <= 0 || decision < need)) {
    AddFinding(findings, Grade::kFail,
               Format("%s shades print alike: %s at b* %.1f, %s at b* %.1f (the palette has them "
                      "%.1f apart)",
                      colour, ShadeName(one), b1, ShadeName(zero), b0, std::abs(design)));
  } else if (gap <= 0) {
    AddFinding(
        findings, Grade::kFail,
        Format("%s shades printed swapped: %s at b* %.1f, %s at b* %.1f (the palette has them "
               "%.1f apart the other way)",
               colour, ShadeName(one), b1, ShadeName(zero), b0, std::abs(design)));
  } else if (decision < need) {
    AddFinding(findings, Grade::kFail,
               Format("%s b* split %.1f (palette %.1f) is gone: decision margin %.1f, the detector "
                      "needs %.1f",
                      colour, gap, std::abs(design), decision, need));
  } else if (gap < o.thin_b_gap || (need > 0 && decision < o.thin_factor * need)) {
    AddFinding(findings, Grade::kWarn,
               Format("%s b* split %.1f (palette %.1f) is thin: decision margin %.1f, %.1f needed",
                      colour, gap, std::abs(design), decision, need));
  }
}

void JudgeColours(const PrintedShades& c, const TagFamily& family, const Palette& palette,
                  const PrintCheckOptions& o, std::vector<Finding>* findings) {
  if (!c.measured) return;
  const Margins& m = c.margins;
  const DetectorOptions& d = o.detector;
  if (m.a_gap < d.adiff_thresh) {
    AddFinding(findings, Grade::kFail,
               Format("reds and greens only %.1f apart in a*, below ADiffThresh %.1f", m.a_gap,
                      d.adiff_thresh));
  } else if (m.a_gap < o.thin_factor * d.adiff_thresh) {
    AddFinding(findings, Grade::kWarn,
               Format("reds and greens %.1f apart in a*: under %.0fx ADiffThresh %.1f", m.a_gap,
                      o.thin_factor, d.adiff_thresh));
  }
  if (m.min_red_a < kMinTagRedA) {
    AddFinding(
        findings, Grade::kFail,
        Format("the paler red prints at a* %.1f, below the detector's floor of %.0f for a red",
               m.min_red_a, kMinTagRedA));
  }
  if (m.max_green_a > d.max_green_a) {
    AddFinding(findings, Grade::kFail,
               Format("the redder green prints at a* %.1f, above max_green_a %.1f", m.max_green_a,
                      d.max_green_a));
  }
  // What an exact read of this family needs (decode.cc); a corrected bit
  // is a fault of its own, judged from the detection.
  const double need = d.min_decision_margin * DecisionMarginFactor(family, 0);
  JudgeBGap("red", Shade::kRed1, Shade::kRed0, m.red_b_gap, m.red_decision, c, palette, need, o,
            findings);
  JudgeBGap("green", Shade::kGreen0, Shade::kGreen1, m.green_b_gap, m.green_decision, c, palette,
            need, o, findings);
}

}  // namespace

void AddFinding(std::vector<Finding>* findings, Grade grade, std::string text) {
  findings->push_back({grade, std::move(text)});
}

void Settle(std::vector<Finding> findings, Grade* grade, std::vector<std::string>* problems,
            std::vector<Grade>* grades) {
  std::stable_sort(findings.begin(), findings.end(), [](const Finding& a, const Finding& b) {
    return static_cast<int>(a.grade) > static_cast<int>(b.grade);
  });
  *grade = Grade::kPass;
  for (const Finding& f : findings) {
    *grade = std::max(*grade, f.grade);
    problems->push_back(f.text);
    grades->push_back(f.grade);
  }
}

namespace {

// A scan's scale: the whole page (fit to page) or one axis (stretched), and
// its skew.
void JudgeScanScale(const PrintCheckOptions& o, const SheetRecord& record, const PrintPageResult& r,
                    std::vector<Finding>* findings) {
  const double tol = o.max_scale_error;
  const double ex = std::max(0.001, 2 * r.scale_x_error), ey = std::max(0.001, 2 * r.scale_y_error);
  const bool x_off = std::abs(r.scale_x - 1.0) > tol, y_off = std::abs(r.scale_y - 1.0) > tol;
  if ((x_off || y_off) && std::abs(r.scale_x - r.scale_y) <= tol) {
    const double mean = (r.scale_x + r.scale_y) / 2;
    AddFinding(findings, Grade::kFail,
               Format("printed at %.1f %% of its size (scale x %.3f ± %.3f, y %.3f ± %.3f; "
                      "allowed 1 ± %.3f): %.1f mm tags print as %.2f mm. Print at 100 %% "
                      "(\"actual size\"), not \"fit to page\"",
                      100 * mean, r.scale_x, ex, r.scale_y, ey, tol, record.tag_size_mm,
                      record.tag_size_mm * mean));
  } else if (x_off || y_off) {
    AddFinding(findings, Grade::kFail,
               Format("stretched: scale x %.3f ± %.3f, y %.3f ± %.3f (allowed 1 ± %.3f each): the "
                      "printer does not keep the page's aspect; poses from these tags will be off",
                      r.scale_x, ex, r.scale_y, ey, tol));
  }
  if (std::abs(r.skew_deg) > 0.5) {
    AddFinding(
        findings, Grade::kWarn,
        Format("the page's axes are %.1f degrees from square (the paper fed crooked)", r.skew_deg));
  }
}

// A photo's aspect: too few tags to judge it, stretched, or too loose a
// view to tell (then the shape was not checked).
void JudgePhotoAspect(const PrintCheckOptions& o, PrintPageResult* r,
                      std::vector<Finding>* findings) {
  if (r->aspect == 0) {
    r->geometry_checked = false;
    AddFinding(
        findings, Grade::kWarn,
        Format("the page's shape was not checked: only %d tag%s fit, too few to judge its aspect "
               "(4 or more)",
               r->tags_in_fit, r->tags_in_fit == 1 ? "" : "s"));
  } else if (std::abs(r->aspect - 1.0) > o.max_aspect_error + 2 * r->aspect_error) {
    AddFinding(
        findings, Grade::kFail,
        Format("stretched: the page's x scale over its y scale is %.3f ± %.3f (allowed 1 ± %.3f)",
               r->aspect, 2 * r->aspect_error, o.max_aspect_error));
  } else if (2 * r->aspect_error > o.max_aspect_error) {
    // The view leaves the aspect too loose to catch a stretch of the
    // tolerance's size (a tilt about one image axis leaves the focal length
    // free, and the aspect trades with it): passing it would vouch for what
    // was not seen.
    r->geometry_checked = false;
    AddFinding(
        findings, Grade::kWarn,
        Format("the page's shape was not checked: this view gives its aspect only as %.3f ± %.3f, "
               "where 1 ± %.3f is allowed (the view does not fix the camera's focal length); "
               "give the camera's intrinsics, add a photo tilted about both axes or face on, or "
               "scan the page",
               r->aspect, 2 * r->aspect_error, o.max_aspect_error));
  }
}

// Detections where the sidecar has no tag.
void JudgeUnexpected(const SheetRecord& record, const PrintPageResult& r,
                     std::vector<Finding>* findings) {
  // A tag of the sheet's family, read exactly, on the page where the sidecar
  // lists none means the sidecar does not describe this print (cut down, or
  // another sheet's); one beside the page, of another family or read with
  // corrected bits may be something else in view.
  for (const UnexpectedDetection& u : r.unexpected) {
    const bool on_page = u.exact && u.center_mm[0] >= 0 && u.center_mm[0] <= record.page.width_mm &&
                         u.center_mm[1] >= 0 && u.center_mm[1] <= record.page.height_mm;
    AddFinding(findings, on_page ? Grade::kFail : Grade::kWarn,
               Format("%s ID %d found at %.1f, %.1f mm, where the sidecar has no tag%s",
                      u.family.c_str(), u.id, u.center_mm[0], u.center_mm[1],
                      on_page ? ": the sidecar does not describe this print" : ""));
  }
}

}  // namespace

void JudgePage(const PrintCheckOptions& o, const SheetRecord& record, PrintPageResult* r,
               std::vector<Finding>* findings) {
  r->geometry_checked = true;  // Unless JudgePhotoAspect says otherwise.
  if (r->scan) {
    JudgeScanScale(o, record, *r, findings);
  } else {
    JudgePhotoAspect(o, r, findings);
  }
  if (r->tags_in_fit >= 3 && r->rms_mm > 0.5 * o.max_position_error_mm) {
    AddFinding(
        findings, Grade::kWarn,
        Format("the tags do not lie on one flat page (fit residual %.2f mm rms): the sheet "
               "curls%s",
               r->rms_mm, r->scan ? "" : " or the lens distorts (give the camera's intrinsics)"));
  }
  JudgeUnexpected(record, *r, findings);
}

void JudgeScanDpi(const PrintImage& image, const PrintPageResult& r,
                  std::vector<Finding>* findings) {
  if (r.scan && image.dpi_from_file &&
      (std::abs(r.scale_x - 1.0) > 0.2 || std::abs(r.scale_y - 1.0) > 0.2)) {
    AddFinding(findings, Grade::kFail,
               Format("the file records %.0f x %.0f dpi: if the scanner used another resolution, "
                      "give the scanner's resolution",
                      image.dpi_x, image.dpi_y));
  }
}

void JudgeTag(const PrintCheckOptions& o, const SheetRecord& record, bool scan,
              double size_allowance, PrintTagResult* t) {
  // What the print did first (the cause), then what the detector made of it.
  std::vector<Finding> findings;
  // A tag's own width carries the detector's corner bias on blurred edges
  // (about 0.3 px an edge, inwards): a pixel is allowed on top.
  const double size_ratio = t->size_mm / record.tag_size_mm;
  if (scan && t->size_mm > 0 && std::abs(size_ratio - 1.0) > o.max_scale_error + size_allowance) {
    AddFinding(&findings, Grade::kFail,
               Format("prints %.2f mm wide where the sidecar says %.2f mm (%.1f %%)", t->size_mm,
                      record.tag_size_mm, 100 * size_ratio));
  }
  JudgeColours(t->colours, *record.family, record.palette, o, &findings);
  if (!t->found) {
    AddFinding(&findings, Grade::kFail, "not found");
  } else if (t->found_id != t->expected.id) {
    AddFinding(&findings, Grade::kFail, Format("decodes as ID %d", t->found_id));
  } else if (t->hamming > 0) {
    AddFinding(&findings, scan ? Grade::kFail : Grade::kWarn,
               Format("decodes only with %d bit%s corrected: a cell reads as the wrong shade",
                      t->hamming, t->hamming == 1 ? "" : "s"));
  }
  if (t->found && t->position_error_mm > o.max_position_error_mm) {
    AddFinding(&findings, Grade::kWarn,
               Format("lies %.2f mm from where the other tags put it", t->position_error_mm));
  }
  Settle(std::move(findings), &t->grade, &t->problems, &t->problem_grades);
}

std::string NoPageProblem(const SheetRecord& record, const DetectionResult& result,
                          const PrintCheckOptions& options, const PrintPageResult& r) {
  std::string why = "no tag of the sheet decodes in this image";
  if (r.undecoded.empty()) {
    if (!result.detections.empty()) why += " (only tags of another sheet or family)";
    return why;
  }
  double red = 0, green = 0, a = 0;
  for (const auto& u : r.undecoded) {
    red += u.red_b_split / r.undecoded.size();
    green += u.green_b_split / r.undecoded.size();
    a += u.a_gap / r.undecoded.size();
  }
  why += Format(
      "; %zu tag-like candidate%s fail to decode, their cells' b* split on average %.1f in "
      "the reds and %.1f in the greens (the palette: %.1f and %.1f), a* gap %.1f",
      r.undecoded.size(), r.undecoded.size() == 1 ? "" : "s", red, green,
      std::abs(record.palette.lab[0].b - record.palette.lab[1].b),
      std::abs(record.palette.lab[3].b - record.palette.lab[2].b), a);
  const double need = options.thin_b_gap / 2;
  if (red < need && green >= need) why += ": the two reds print alike";
  if (green < need && red >= need) why += ": the two greens print alike";
  if (red < need && green < need) why += ": neither colour's two shades can be told apart";
  return why;
}

}  // namespace chromatag::internal
