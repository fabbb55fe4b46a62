// The print check's geometry (print_geometry.h): the page fit and what it
// measures. The fits are OpenCV's: a least-squares affine map (cv::solve,
// with its parameters' standard errors) for scans, cv::findHomography over
// every corner for photos; lens distortion is the detector's (camera.h).
#include "print_geometry.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/camera.h"
#include "chromatag/families/color.h"
#include "print_internal.h"

namespace chromatag::internal {
namespace {

// Least squares: page mm -> `image` points (scan mm for a scan, pixels for a
// photo), affine or projective.
bool FitOnce(const std::vector<cv::Point2d>& page, const std::vector<cv::Point2d>& image,
             bool affine, PageFit* fit) {
  if (affine) {
    cv::Mat a(static_cast<int>(page.size()), 3, CV_64F), bx(a.rows, 1, CV_64F),
        by(a.rows, 1, CV_64F);
    for (int i = 0; i < a.rows; ++i) {
      a.at<double>(i, 0) = page[i].x;
      a.at<double>(i, 1) = page[i].y;
      a.at<double>(i, 2) = 1.0;
      bx.at<double>(i) = image[i].x;
      by.at<double>(i) = image[i].y;
    }
    cv::Mat px, py;
    if (!cv::solve(a, bx, px, cv::DECOMP_SVD) || !cv::solve(a, by, py, cv::DECOMP_SVD))
      return false;
    fit->image_from_page =
        cv::Matx33d(px.at<double>(0), px.at<double>(1), px.at<double>(2), py.at<double>(0),
                    py.at<double>(1), py.at<double>(2), 0, 0, 1);
    const cv::Mat rx = a * px - bx, ry = a * py - by;
    const int dof = 2 * a.rows - 6;
    if (dof > 0) {
      const double s2 = (rx.dot(rx) + ry.dot(ry)) / dof;
      const cv::Mat m = (a.t() * a).inv(cv::DECOMP_SVD);
      fit->se_x = std::sqrt(s2 * m.at<double>(0, 0));
      fit->se_y = std::sqrt(s2 * m.at<double>(1, 1));
    }
    return true;
  }
  const cv::Mat h = cv::findHomography(page, image, 0);
  if (h.empty()) return false;
  fit->image_from_page = cv::Matx33d(h);
  return true;
}

// The page's x scale over its y scale in a photo, from the homography and
// the camera (K): H ~ K [r1 r2 t] diag(sx, sy, 1).
double AspectOf(const cv::Matx33d& h, const cv::Matx33d& k) {
  const cv::Matx33d m = k.inv() * h;
  const double n1 = std::hypot(std::hypot(m(0, 0), m(1, 0)), m(2, 0));
  const double n2 = std::hypot(std::hypot(m(0, 1), m(1, 1)), m(2, 1));
  return n1 / n2;
}

// Focal length from the orthogonality of the page's axes with the principal
// point at (cx, cy) and square pixels; nullopt when the view is too close
// to face-on (or too noisy) to tell.
std::optional<double> EstimateFocal(const cv::Matx33d& h, double cx, double cy, double width) {
  const cv::Matx33d t(1, 0, -cx, 0, 1, -cy, 0, 0, 1);
  const cv::Matx33d g = t * h;
  const double num = -(g(0, 0) * g(0, 1) + g(1, 0) * g(1, 1));
  const double den = g(2, 0) * g(2, 1);
  if (std::abs(den) < 1e-15) return std::nullopt;
  const double f2 = num / den;
  if (!(f2 > 0)) return std::nullopt;
  const double f = std::sqrt(f2);
  if (f < 0.25 * width || f > 8.0 * width) return std::nullopt;
  return f;
}

struct AspectEstimate {
  double aspect = 0.0;  // 0 when the points give no homography.
  double focal = 0.0;
  bool focal_found = false;  // Estimated from the perspective (or given).
};

// The page's aspect from page points and their (undistorted) pixels, with
// the camera `k` if known, else a focal length from the page's perspective
// and the principal point at (cx, cy).
AspectEstimate EstimateAspect(const std::vector<cv::Point2d>& page,
                              const std::vector<cv::Point2d>& image,
                              const std::optional<cv::Matx33d>& k, double cx, double cy,
                              double width) {
  AspectEstimate out;
  const cv::Mat hm = cv::findHomography(page, image, 0);
  if (hm.empty()) return out;
  const cv::Matx33d h(hm);
  if (k) {
    out.focal = std::sqrt((*k)(0, 0) * (*k)(1, 1));
    out.focal_found = true;
    out.aspect = AspectOf(h, *k);
    return out;
  }
  const auto f = EstimateFocal(h, cx, cy, width);
  out.focal_found = f.has_value();
  out.focal = f ? *f : 0.87 * width;
  out.aspect = AspectOf(h, cv::Matx33d(out.focal, 0, cx, 0, out.focal, cy, 0, 0, 1));
  return out;
}

}  // namespace

FitSpace::FitSpace(const PrintImage& image, const std::optional<CameraIntrinsics>& camera)
    : scan_(image.dpi_x > 0 && image.dpi_y > 0),
      mm_per_px_x_(scan_ ? kMmPerInch / image.dpi_x : 1.0),
      mm_per_px_y_(scan_ ? kMmPerInch / image.dpi_y : 1.0) {
  if (!scan_ && camera && !camera->distortion.empty()) camera_ = camera;
}

cv::Point2d FitSpace::FromImage(const cv::Point2d& px) const {
  if (scan_) return {px.x * mm_per_px_x_, px.y * mm_per_px_y_};
  if (!camera_) return px;
  return UndistortPoints(*camera_, {px})[0];
}

std::vector<cv::Point2d> FitSpace::ToImage(const std::vector<cv::Point2d>& points) const {
  std::vector<cv::Point2d> out;
  if (scan_ || !camera_) {
    for (const cv::Point2d& p : points)
      out.push_back(scan_ ? cv::Point2d(p.x / mm_per_px_x_, p.y / mm_per_px_y_) : p);
    return out;
  }
  // Undistorted pixels to normalised rays, then through the lens.
  std::vector<cv::Point3d> rays;
  const cv::Matx33d k_inv = CameraMatrix(*camera_).inv();
  for (const cv::Point2d& p : points) {
    const cv::Vec3d ray = k_inv * cv::Vec3d(p.x, p.y, 1.0);
    rays.emplace_back(ray[0] / ray[2], ray[1] / ray[2], 1.0);
  }
  return ProjectPoints(*camera_, rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0));
}

cv::Matx33d FitSpace::PixelsFromFit() const {
  return scan_ ? cv::Matx33d(1 / mm_per_px_x_, 0, 0, 0, 1 / mm_per_px_y_, 0, 0, 0, 1)
               : cv::Matx33d::eye();
}

int ChoosePage(const SheetRecord& record, const std::vector<const Detection*>& mine) {
  std::vector<int> votes(std::max(1, record.num_pages), 0);
  for (const Detection* d : mine) {
    std::vector<bool> voted(votes.size(), false);
    for (const PlacedTag& t : record.tags) {
      if (t.id == d->id && t.page < static_cast<int>(votes.size()) && !voted[t.page]) {
        ++votes[t.page];
        voted[t.page] = true;
      }
    }
  }
  const auto best = std::max_element(votes.begin(), votes.end());
  return *best > 0 ? static_cast<int>(best - votes.begin()) : -1;
}

std::vector<Pair> PairByIds(const std::vector<PlacedTag>& tags,
                            const std::vector<const Detection*>& mine) {
  std::vector<Pair> pairs;
  for (size_t k = 0; k < mine.size(); ++k) {
    int match = -1, count = 0;
    for (size_t i = 0; i < tags.size(); ++i) {
      if (tags[i].id != mine[k]->id) continue;
      match = static_cast<int>(i);
      ++count;
    }
    if (count == 1) pairs.push_back({match, static_cast<int>(k)});
  }
  return pairs;
}

std::optional<PageFit> FitPage(const std::vector<PlacedTag>& tags,
                               const std::vector<std::array<cv::Point2d, 4>>& found_corners,
                               const std::vector<Pair>& pairs, bool affine, double drop_mm) {
  std::vector<int> kept(pairs.size());
  std::iota(kept.begin(), kept.end(), 0);
  while (true) {
    std::vector<cv::Point2d> page, image;
    for (int k : kept) {
      for (int c = 0; c < 4; ++c) {
        page.emplace_back(tags[pairs[k].tag].corners_mm[c][0], tags[pairs[k].tag].corners_mm[c][1]);
        image.push_back(found_corners[pairs[k].detection][c]);
      }
    }
    PageFit fit;
    if (!FitOnce(page, image, affine, &fit)) return std::nullopt;
    const cv::Matx33d page_from_image = fit.image_from_page.inv();
    double worst = 0.0, sum2 = 0.0;
    size_t worst_k = 0;
    std::vector<double> tag_errors;
    for (size_t i = 0; i < kept.size(); ++i) {
      double tag_worst = 0.0;
      for (int c = 0; c < 4; ++c) {
        const cv::Point2d back = ApplyHomography(page_from_image, image[4 * i + c]);
        const double e = cv::norm(back - page[4 * i + c]);
        sum2 += e * e;
        tag_worst = std::max(tag_worst, e);
      }
      tag_errors.push_back(tag_worst);
      if (tag_worst > worst) worst = tag_worst, worst_k = i;
    }
    fit.rms_mm = std::sqrt(sum2 / std::max<size_t>(1, page.size()));
    // An outlier lies off by more than drop_mm and well beyond the others:
    // a curled page or a distorting lens moves every tag a little, and
    // dropping them one by one would leave a fit over two.
    std::nth_element(tag_errors.begin(), tag_errors.begin() + tag_errors.size() / 2,
                     tag_errors.end());
    const double typical = tag_errors[tag_errors.size() / 2];
    if (worst <= std::max(drop_mm, 4.0 * typical) || kept.size() <= 2) {
      fit.kept = kept;
      return fit;
    }
    kept.erase(kept.begin() + worst_k);
  }
}

void MeasureScale(const PageFit& fit, PrintPageResult* r) {
  const cv::Matx33d& a = fit.image_from_page;
  r->scale_x = std::hypot(a(0, 0), a(1, 0));
  r->scale_y = std::hypot(a(0, 1), a(1, 1));
  r->scale_x_error = fit.se_x;
  r->scale_y_error = fit.se_y;
  const double cos_angle =
      (a(0, 0) * a(0, 1) + a(1, 0) * a(1, 1)) / std::max(1e-12, r->scale_x * r->scale_y);
  r->skew_deg = std::asin(std::clamp(cos_angle, -1.0, 1.0)) * 180.0 / kPi;
}

void MeasureAspect(const std::vector<cv::Point2d>& page, const std::vector<cv::Point2d>& image,
                   const std::optional<CameraIntrinsics>& camera, cv::Size size,
                   PrintPageResult* r) {
  const size_t n = page.size() / 4;
  if (n < 4) return;  // Too few to judge (JudgePage says so).
  std::optional<cv::Matx33d> k;
  if (camera) k = cv::Matx33d(camera->fx, 0, camera->cx, 0, camera->fy, camera->cy, 0, 0, 1);
  const double cx = (size.width - 1) / 2.0, cy = (size.height - 1) / 2.0;
  const AspectEstimate all = EstimateAspect(page, image, k, cx, cy, size.width);
  if (!(all.aspect > 0)) return;
  r->aspect = all.aspect;
  r->focal_px = all.focal;
  r->focal_source = k ? "camera" : all.focal_found ? "perspective" : "guessed";
  std::vector<double> partial;
  for (size_t leave = 0; leave < n; ++leave) {
    std::vector<cv::Point2d> p2, i2;
    for (size_t i = 0; i < page.size(); ++i) {
      if (i / 4 == leave) continue;
      p2.push_back(page[i]);
      i2.push_back(image[i]);
    }
    const AspectEstimate e = EstimateAspect(p2, i2, k, cx, cy, size.width);
    if (e.aspect > 0) partial.push_back(e.aspect);
  }
  if (partial.size() >= 2) {
    const double mean = std::accumulate(partial.begin(), partial.end(), 0.0) / partial.size();
    double sum = 0.0;
    for (double a : partial) sum += (a - mean) * (a - mean);
    r->aspect_error = std::sqrt(sum * (partial.size() - 1) / partial.size());
  }
  if (!k && !all.focal_found) {
    // Face on, the focal length cannot be told, and barely matters: a
    // usual camera's (about 60 degrees across) was taken; let the spread
    // over half to twice it say how little.
    for (double f : {all.focal / 2, all.focal * 2}) {
      const AspectEstimate e =
          EstimateAspect(page, image, cv::Matx33d(f, 0, cx, 0, f, cy, 0, 0, 1), cx, cy, size.width);
      if (e.aspect > 0)
        r->aspect_error = std::max(r->aspect_error, std::abs(e.aspect - r->aspect) / 2);
    }
  }
}

double LeaveOneOutError(const std::vector<PlacedTag>& tags,
                        const std::vector<std::array<cv::Point2d, 4>>& fit_corners,
                        const std::vector<Pair>& pairs, const PageFit& fit, int k, bool affine) {
  cv::Matx33d fit_from_page = fit.image_from_page;
  const bool kept = std::find(fit.kept.begin(), fit.kept.end(), k) != fit.kept.end();
  if (kept && fit.kept.size() >= 3) {
    std::vector<cv::Point2d> page, image;
    for (int other : fit.kept) {
      if (other == k) continue;
      for (int c = 0; c < 4; ++c) {
        page.emplace_back(tags[pairs[other].tag].corners_mm[c][0],
                          tags[pairs[other].tag].corners_mm[c][1]);
        image.push_back(fit_corners[pairs[other].detection][c]);
      }
    }
    PageFit without;
    if (FitOnce(page, image, affine, &without)) fit_from_page = without.image_from_page;
  }
  const cv::Matx33d page_from_fit = fit_from_page.inv();
  double worst = 0.0;
  for (int c = 0; c < 4; ++c) {
    const cv::Point2d back = ApplyHomography(page_from_fit, fit_corners[pairs[k].detection][c]);
    const auto& mm = tags[pairs[k].tag].corners_mm[c];
    worst = std::max(worst, std::hypot(back.x - mm[0], back.y - mm[1]));
  }
  return worst;
}

cv::Mat PageView(const cv::Mat& bgr, const cv::Matx33d& fit_from_page, const FitSpace& space,
                 const PageSize& page, double s) {
  const cv::Size size(std::max(1, static_cast<int>(std::lround(page.width_mm * s))),
                      std::max(1, static_cast<int>(std::lround(page.height_mm * s))));
  // View pixel (u, v) is page mm ((u + 0.5) / s, (v + 0.5) / s).
  std::vector<cv::Point2d> fit;
  fit.reserve(static_cast<size_t>(size.area()));
  for (int v = 0; v < size.height; ++v)
    for (int u = 0; u < size.width; ++u)
      fit.push_back(ApplyHomography(fit_from_page, {(u + 0.5) / s, (v + 0.5) / s}));
  const std::vector<cv::Point2d> image = space.ToImage(fit);
  cv::Mat map(size, CV_32FC2);
  for (int v = 0; v < size.height; ++v) {
    for (int u = 0; u < size.width; ++u) {
      const cv::Point2d& p = image[static_cast<size_t>(v) * size.width + u];
      map.at<cv::Vec2f>(v, u) = cv::Vec2f(static_cast<float>(p.x), static_cast<float>(p.y));
    }
  }
  cv::Mat view;
  cv::remap(bgr, view, map, cv::noArray(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(128, 128, 128));
  return view;
}

}  // namespace chromatag::internal
