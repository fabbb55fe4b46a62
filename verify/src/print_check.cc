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

using Quad = std::array<cv::Point2d, 4>;

cv::Point2d Centre(const Quad& q) { return (q[0] + q[1] + q[2] + q[3]) * 0.25; }

// The page of the sheet an image shows, its tags, the detections of the
// sheet's family and the fit between them.
struct PageMatch {
  std::vector<const Detection*> mine;  // The detections of the sheet's family.
  std::vector<PlacedTag> tags;         // The page's tags.
  std::vector<Quad> fit_corners;       // Per detection of `mine`, in fit space.
  std::vector<internal::Pair> pairs;
  internal::PageFit fit;
};

Quad ToFitSpace(const internal::FitSpace& space, const Quad& corners) {
  Quad q;
  for (int c = 0; c < 4; ++c) q[c] = space.FromImage(corners[c]);
  return q;
}

// The detections of `family`.
std::vector<const Detection*> OfFamily(const DetectionResult& result, const TagFamily* family) {
  std::vector<const Detection*> mine;
  for (const Detection& d : result.detections)
    if (d.family == family) mine.push_back(&d);
  return mine;
}

// Pairs the page's tags with the detections by ID and fits the page over
// their corners (affine for a scan); false when there is no fit.
bool FitPageToTags(const internal::FitSpace& space, const PrintCheckOptions& options, bool scan,
                   PageMatch* m) {
  for (const Detection* d : m->mine) m->fit_corners.push_back(ToFitSpace(space, d->corners));
  m->pairs = internal::PairByIds(m->tags, m->mine);
  const auto fit = m->pairs.empty() ? std::nullopt
                                    : internal::FitPage(m->tags, m->fit_corners, m->pairs, scan,
                                                        options.max_position_error_mm);
  if (!fit) return false;
  m->fit = *fit;
  return true;
}

// Where fitted corners' centre lies on the page.
cv::Point2d OnPage(const cv::Matx33d& page_from_fit, const Quad& fitted) {
  return ApplyHomography(page_from_fit, Centre(fitted));
}

// The page's geometry: a scan's scale, a photo's aspect.
void MeasurePageGeometry(const PageMatch& m, const cv::Mat& bgr, const PrintCheckOptions& options,
                         PrintPageResult* r) {
  if (r->scan) {
    internal::MeasureScale(m.fit, r);
    return;
  }
  std::vector<cv::Point2d> page, fitted;
  for (int kept : m.fit.kept) {
    for (int c = 0; c < 4; ++c) {
      const auto& mm = m.tags[m.pairs[kept].tag].corners_mm[c];
      page.emplace_back(mm[0], mm[1]);
      fitted.push_back(m.fit_corners[m.pairs[kept].detection][c]);
    }
  }
  internal::MeasureAspect(page, fitted, options.camera, bgr.size(), r);
}

// Per detection, the page's tag it lies on (its centre within half a tag of
// the tag's, on the page); -1 for none.
std::vector<int> TagOwners(const PageMatch& m, double tag_size_mm,
                           const cv::Matx33d& page_from_fit) {
  std::vector<int> owner(m.mine.size(), -1);
  for (size_t k = 0; k < m.mine.size(); ++k) {
    const cv::Point2d c = OnPage(page_from_fit, m.fit_corners[k]);
    double best = 0.5 * tag_size_mm;
    for (size_t i = 0; i < m.tags.size(); ++i) {
      const double dist = std::hypot(c.x - m.tags[i].center_mm[0], c.y - m.tags[i].center_mm[1]);
      if (dist < best) best = dist, owner[k] = static_cast<int>(i);
    }
  }
  return owner;
}

// The detection lying on tag i, one with the tag's ID first; -1 for none.
int DetectionOnTag(const PageMatch& m, const std::vector<int>& owner, size_t i) {
  int found = -1;
  for (size_t k = 0; k < m.mine.size(); ++k) {
    if (owner[k] != static_cast<int>(i)) continue;
    if (found < 0 || (m.mine[k]->id == m.tags[i].id && m.mine[found]->id != m.tags[i].id))
      found = static_cast<int>(k);
  }
  return found;
}

// Detection `found` on tag i: what it read, and when that is the tag's ID,
// its corners, its distance from where the other tags put it and (a scan)
// its size. Returns the allowance on the size the shades' reading takes.
double ReadFoundTag(const PageMatch& m, int found, size_t i, const PrintImage& image,
                    PrintPageResult* r, PrintTagResult* t) {
  const Detection& d = *m.mine[found];
  t->found = true;
  t->found_id = d.id;
  t->hamming = d.hamming;
  t->margin = d.decision_margin;
  if (d.id != m.tags[i].id) return 0.0;
  t->corners_px = d.corners;
  ++r->tags_found;
  const auto pair = std::find_if(m.pairs.begin(), m.pairs.end(),
                                 [&](const internal::Pair& p) { return p.detection == found; });
  if (pair != m.pairs.end()) {
    t->position_error_mm = internal::LeaveOneOutError(
        m.tags, m.fit_corners, m.pairs, m.fit, static_cast<int>(pair - m.pairs.begin()), r->scan);
  }
  if (!r->scan) return 0.0;
  const auto& q = m.fit_corners[found];
  t->size_mm = (cv::norm(q[1] - q[0]) + cv::norm(q[2] - q[1]) + cv::norm(q[3] - q[2]) +
                cv::norm(q[0] - q[3])) /
               4.0;
  const double px_per_mm = (image.dpi_x + image.dpi_y) / 2 / internal::kMmPerInch;
  return 1.0 / std::max(1.0, t->size_mm * px_per_mm);
}

// Tag i of the page: the detection lying on it, else where the fit puts it;
// its shades read there and judged.
PrintTagResult CheckTag(const PageMatch& m, const std::vector<int>& owner, size_t i,
                        const SheetRecord& record, const cv::Mat& bgr, const PrintImage& image,
                        const internal::FitSpace& space, const PrintCheckOptions& options,
                        PrintPageResult* r) {
  const PlacedTag& tag = m.tags[i];
  PrintTagResult t;
  t.expected = tag;
  const int found = DetectionOnTag(m, owner, i);
  std::vector<cv::Point2d> predicted;
  for (int c = 0; c < 4; ++c)
    predicted.push_back(
        ApplyHomography(m.fit.image_from_page, {tag.corners_mm[c][0], tag.corners_mm[c][1]}));
  predicted = space.ToImage(predicted);
  std::copy(predicted.begin(), predicted.end(), t.corners_px.begin());
  const double size_allowance = found >= 0 ? ReadFoundTag(m, found, i, image, r, &t) : 0.0;
  t.colours = internal::ReadPrintedShades(bgr, t.corners_px, *record.family,
                                          record.quiet_zone_cells, record.family->CodeOf(tag.id));
  internal::JudgeTag(options, record, r->scan, size_allowance, &t);
  return t;
}

// Detections on none of the page's tags, and those of other families, with
// where they lie on the page.
void ListUnexpected(const PageMatch& m, const std::vector<int>& owner,
                    const DetectionResult& result, const SheetRecord& record,
                    const internal::FitSpace& space, const cv::Matx33d& page_from_fit,
                    PrintPageResult* r) {
  for (size_t k = 0; k < m.mine.size(); ++k) {
    if (owner[k] >= 0) continue;
    const cv::Point2d c = OnPage(page_from_fit, m.fit_corners[k]);
    r->unexpected.push_back(
        {r->page, m.mine[k]->family->name(), m.mine[k]->id, {c.x, c.y}, m.mine[k]->hamming == 0});
  }
  for (const Detection& d : result.detections) {
    if (d.family == record.family.get()) continue;
    const cv::Point2d c = OnPage(page_from_fit, ToFitSpace(space, d.corners));
    r->unexpected.push_back({r->page, d.family->name(), d.id, {c.x, c.y}});
  }
}

// The image resampled onto the page for the report, at most 4000 pixels
// on its longer side and 3 a millimetre.
void DrawPageView(const SheetRecord& record, const cv::Mat& bgr, const internal::PageFit& fit,
                  const internal::FitSpace& space, PrintPageResult* r) {
  const double max_side = std::max(record.page.width_mm, record.page.height_mm);
  r->view_px_per_mm = std::min(3.0, 4000.0 / max_side);
  r->page_view =
      internal::PageView(bgr, fit.image_from_page, space, record.page, r->view_px_per_mm);
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
  PageMatch m;
  m.mine = OfFamily(result, record.family.get());
  r.page = internal::ChoosePage(record, m.mine);
  if (r.page < 0) {
    r.undecoded = internal::Undecoded(bgr, result, record);
    AddFinding(&page_findings, Grade::kFail, internal::NoPageProblem(record, result, options, r));
    return settle();
  }
  for (const PlacedTag& t : record.tags)
    if (t.page == r.page) m.tags.push_back(t);

  // 2. One fit from page millimetres over every paired tag's corners.
  if (!FitPageToTags(space, options, r.scan, &m)) {
    AddFinding(&page_findings, Grade::kFail, "the found tags do not fit the sheet's layout");
    return settle();
  }
  r.image_from_page = space.PixelsFromFit() * m.fit.image_from_page;
  r.tags_in_fit = static_cast<int>(m.fit.kept.size());
  r.rms_mm = m.fit.rms_mm;

  // 3. The page's geometry: a scan's scale, a photo's aspect.
  MeasurePageGeometry(m, bgr, options, &r);

  // 4. Every tag of the page, and what lies on none of them.
  const cv::Matx33d page_from_fit = m.fit.image_from_page.inv();
  const std::vector<int> owner = TagOwners(m, record.tag_size_mm, page_from_fit);
  for (size_t i = 0; i < m.tags.size(); ++i)
    r.tags.push_back(CheckTag(m, owner, i, record, bgr, image, space, options, &r));
  ListUnexpected(m, owner, result, record, space, page_from_fit, &r);

  // 5. The page's verdict, and its view for the report.
  internal::JudgePage(options, record, &r, &page_findings);
  internal::JudgeScanDpi(image, r, &page_findings);
  DrawPageView(record, bgr, m.fit, space, &r);
  return settle();
}

}  // namespace chromatag
