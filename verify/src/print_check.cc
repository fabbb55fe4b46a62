// verify --print for one image (print_check.h): detects the sheet's tags,
// chooses the page they belong to, fits it (print_geometry.h), measures every
// tag of the page where it was found or where the fit puts it
// (print_colours.h), and judges page and tags (print_verdict.h).
#include "chromatag/verify/print_check.h"

#include <algorithm>
#include <cmath>

#include "print_colours.h"
#include "print_geometry.h"
#include "print_internal.h"
#include "print_verdict.h"

namespace chromatag {
namespace {

using internal::AddFinding;
using internal::ApplyHomography;
using internal::Finding;

cv::Point2d Centre(const std::array<cv::Point2d, 4>& q) {
  return (q[0] + q[1] + q[2] + q[3]) * 0.25;
}

}  // namespace

bool PrintCheckOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (scan_dpi != 0.0 && !(scan_dpi >= 50.0 && scan_dpi <= 4800.0))
    return fail("the scan resolution must be in [50, 4800] dpi");
  if (!(max_scale_error > 0.0 && max_scale_error <= 0.2))
    return fail("the scale tolerance must be in (0, 0.2] (0.005 is 0.5 %)");
  if (!(max_aspect_error > 0.0 && max_aspect_error <= 0.2))
    return fail("the aspect tolerance must be in (0, 0.2]");
  if (!(max_position_error_mm > 0.0 && max_position_error_mm <= 50.0))
    return fail("the position tolerance must be in (0, 50] mm");
  if (!(thin_b_gap >= 0.0 && thin_b_gap <= 100.0) || !(thin_factor >= 1.0 && thin_factor <= 10.0))
    return fail("thin_b_gap must be in [0, 100] and thin_factor in [1, 10]");
  if (camera && !camera->IsValid(error)) return false;
  return detector.IsValid(error);
}

const char* GradeName(Grade grade) {
  switch (grade) {
    case Grade::kPass:
      return "pass";
    case Grade::kWarn:
      return "warn";
    case Grade::kFail:
      return "fail";
  }
  return "?";
}

PrintPageResult CheckPrintImage(const SheetRecord& record, const cv::Mat& bgr,
                                const PrintImage& image, const Detector& detector,
                                const PrintCheckOptions& options) {
  PrintPageResult r;
  r.image = image.name;
  r.image_size = bgr.size();
  const internal::FitSpace space(image, options.camera);
  r.scan = space.scan();
  r.dpi_x = image.dpi_x;
  r.dpi_y = image.dpi_y;
  std::vector<Finding> page_findings;
  auto settle = [&] {
    internal::Settle(std::move(page_findings), &r.grade, &r.problems, &r.problem_grades);
    for (const PrintTagResult& t : r.tags) r.grade = std::max(r.grade, t.grade);
    return r;
  };
  std::string why;
  if (!internal::SheetIsSane(record, &why)) {
    AddFinding(&page_findings, Grade::kFail, "sidecar '" + record.sidecar_path + "': " + why);
    return settle();
  }

  // 1. Which page: the one most of the sheet's detected IDs belong to.
  const DetectionResult result = detector.Detect(bgr, PixelOrder::kBgr);
  std::vector<const Detection*> mine;
  for (const Detection& d : result.detections)
    if (d.family == record.family.get()) mine.push_back(&d);
  r.page = internal::ChoosePage(record, mine);
  if (r.page < 0) {
    r.undecoded = internal::Undecoded(bgr, result, record);
    AddFinding(&page_findings, Grade::kFail, internal::NoPageProblem(record, result, options, r));
    return settle();
  }
  std::vector<PlacedTag> tags;
  for (const PlacedTag& t : record.tags)
    if (t.page == r.page) tags.push_back(t);

  // 2. One fit from page millimetres over every paired tag's corners.
  std::vector<std::array<cv::Point2d, 4>> fit_corners;
  for (const Detection* d : mine) {
    std::array<cv::Point2d, 4> q;
    for (int c = 0; c < 4; ++c) q[c] = space.FromImage(d->corners[c]);
    fit_corners.push_back(q);
  }
  const std::vector<internal::Pair> pairs = internal::PairByIds(tags, mine);
  const auto fit = pairs.empty() ? std::nullopt
                                 : internal::FitPage(tags, fit_corners, pairs, r.scan,
                                                     options.max_position_error_mm);
  if (!fit) {
    AddFinding(&page_findings, Grade::kFail, "the found tags do not fit the sheet's layout");
    return settle();
  }
  r.image_from_page = space.PixelsFromFit() * fit->image_from_page;
  r.tags_in_fit = static_cast<int>(fit->kept.size());
  r.rms_mm = fit->rms_mm;

  // 3. The page's geometry: a scan's scale, a photo's aspect.
  if (r.scan) {
    internal::MeasureScale(*fit, &r);
  } else {
    std::vector<cv::Point2d> page, fitted;
    for (int kept : fit->kept) {
      for (int c = 0; c < 4; ++c) {
        const auto& mm = tags[pairs[kept].tag].corners_mm[c];
        page.emplace_back(mm[0], mm[1]);
        fitted.push_back(fit_corners[pairs[kept].detection][c]);
      }
    }
    internal::MeasureAspect(page, fitted, options.camera, bgr.size(), &r);
  }

  // 4. Every tag of the page: the detection lying on it (its centre within
  // half a tag of the tag's, on the page), else where the fit puts it.
  const cv::Matx33d page_from_fit = fit->image_from_page.inv();
  auto on_page = [&](const std::array<cv::Point2d, 4>& fitted) {
    return ApplyHomography(page_from_fit, Centre(fitted));
  };
  std::vector<int> owner(mine.size(), -1);
  for (size_t k = 0; k < mine.size(); ++k) {
    const cv::Point2d c = on_page(fit_corners[k]);
    double best = 0.5 * record.tag_size_mm;
    for (size_t i = 0; i < tags.size(); ++i) {
      const double dist = std::hypot(c.x - tags[i].center_mm[0], c.y - tags[i].center_mm[1]);
      if (dist < best) best = dist, owner[k] = static_cast<int>(i);
    }
  }
  for (size_t i = 0; i < tags.size(); ++i) {
    PrintTagResult t;
    t.expected = tags[i];
    int found = -1;
    for (size_t k = 0; k < mine.size(); ++k) {
      if (owner[k] != static_cast<int>(i)) continue;
      if (found < 0 || (mine[k]->id == tags[i].id && mine[found]->id != tags[i].id))
        found = static_cast<int>(k);
    }
    std::vector<cv::Point2d> predicted;
    for (int c = 0; c < 4; ++c)
      predicted.push_back(ApplyHomography(fit->image_from_page,
                                          {tags[i].corners_mm[c][0], tags[i].corners_mm[c][1]}));
    predicted = space.ToImage(predicted);
    std::copy(predicted.begin(), predicted.end(), t.corners_px.begin());
    double size_allowance = 0.0;
    if (found >= 0) {
      const Detection& d = *mine[found];
      t.found = true;
      t.found_id = d.id;
      t.hamming = d.hamming;
      t.margin = d.decision_margin;
      if (d.id == tags[i].id) {
        t.corners_px = d.corners;
        ++r.tags_found;
        const auto pair = std::find_if(pairs.begin(), pairs.end(), [&](const internal::Pair& p) {
          return p.detection == found;
        });
        if (pair != pairs.end()) {
          t.position_error_mm = internal::LeaveOneOutError(
              tags, fit_corners, pairs, *fit, static_cast<int>(pair - pairs.begin()), r.scan);
        }
        if (r.scan) {
          const auto& q = fit_corners[found];
          t.size_mm = (cv::norm(q[1] - q[0]) + cv::norm(q[2] - q[1]) + cv::norm(q[3] - q[2]) +
                       cv::norm(q[0] - q[3])) /
                      4.0;
          const double px_per_mm = (image.dpi_x + image.dpi_y) / 2 / internal::kMmPerInch;
          size_allowance = 1.0 / std::max(1.0, t.size_mm * px_per_mm);
        }
      }
    }
    t.colours =
        internal::ReadPrintedShades(bgr, t.corners_px, *record.family, record.quiet_zone_cells,
                                    record.family->CodeOf(tags[i].id));
    internal::JudgeTag(options, record, r.scan, size_allowance, &t);
    r.tags.push_back(std::move(t));
  }
  for (size_t k = 0; k < mine.size(); ++k) {
    if (owner[k] >= 0) continue;
    const cv::Point2d c = on_page(fit_corners[k]);
    r.unexpected.push_back(
        {r.page, mine[k]->family->name(), mine[k]->id, {c.x, c.y}, mine[k]->hamming == 0});
  }
  for (const Detection& d : result.detections) {
    if (d.family == record.family.get()) continue;
    std::array<cv::Point2d, 4> q;
    for (int c = 0; c < 4; ++c) q[c] = space.FromImage(d.corners[c]);
    const cv::Point2d c = on_page(q);
    r.unexpected.push_back({r.page, d.family->name(), d.id, {c.x, c.y}});
  }

  // 5. The page's verdict, and its view for the report.
  internal::JudgePage(options, record, &r, &page_findings);
  internal::JudgeScanDpi(image, r, &page_findings);
  const double max_side = std::max(record.page.width_mm, record.page.height_mm);
  r.view_px_per_mm = std::min(3.0, 4000.0 / max_side);
  r.page_view = internal::PageView(bgr, fit->image_from_page, space, record.page, r.view_px_per_mm);
  return settle();
}

}  // namespace chromatag
