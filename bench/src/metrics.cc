#include "chromatag/bench/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/families/color.h"
#include "chromatag/families/family.h"

namespace chromatag::bench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double SignedArea(const std::vector<cv::Point2f>& polygon) {
  double twice = 0.0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const cv::Point2f& a = polygon[i];
    const cv::Point2f& b = polygon[(i + 1) % polygon.size()];
    twice += static_cast<double>(a.x) * b.y - static_cast<double>(b.x) * a.y;
  }
  return twice / 2.0;
}

std::vector<cv::Point2f> CounterClockwise(const Quad& quad) {
  std::vector<cv::Point2f> polygon(quad.begin(), quad.end());
  if (SignedArea(polygon) < 0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

// Fallback for non-convex or self-crossing quads (a broken detection): count
// pixels of both filled polygons on a grid 8 times finer than the image.
double RasterIoU(const Quad& a, const Quad& b) {
  cv::Rect2d box = cv::boundingRect(std::vector<cv::Point2f>(a.begin(), a.end()));
  box |= cv::Rect2d(cv::boundingRect(std::vector<cv::Point2f>(b.begin(), b.end())));
  constexpr int kScale = 8;
  const cv::Size size(static_cast<int>(box.width * kScale) + 2,
                      static_cast<int>(box.height * kScale) + 2);
  if (size.area() > 16'000'000) return 0.0;  // Absurd detections do not match.
  auto fill = [&](const Quad& quad) {
    cv::Mat mask = cv::Mat::zeros(size, CV_8UC1);
    std::vector<cv::Point> points;
    for (const auto& p : quad) {
      points.emplace_back(static_cast<int>(std::lround((p.x - box.x) * kScale)),
                          static_cast<int>(std::lround((p.y - box.y) * kScale)));
    }
    cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{points}, cv::Scalar(1));
    return mask;
  };
  const cv::Mat ma = fill(a), mb = fill(b);
  const double both = cv::countNonZero(ma & mb), either = cv::countNonZero(ma | mb);
  return either > 0 ? both / either : 0.0;
}

}  // namespace

double QuadIoU(const Quad& a, const Quad& b) {
  const std::vector<cv::Point2f> pa = CounterClockwise(a), pb = CounterClockwise(b);
  if (!cv::isContourConvex(pa) || !cv::isContourConvex(pb)) return RasterIoU(a, b);
  const double area_a = std::abs(SignedArea(pa)), area_b = std::abs(SignedArea(pb));
  if (area_a <= 0.0 || area_b <= 0.0) return 0.0;
  std::vector<cv::Point2f> overlap;
  const double both = cv::intersectConvexConvex(pa, pb, overlap, true);
  if (both <= 0.0) return 0.0;
  return both / (area_a + area_b - both);
}

FrameScore ScoreFrame(const std::vector<FoundTag>& found, const TagTruth* truth,
                      const TagTruth* other, double min_iou) {
  FrameScore score;
  for (size_t index = 0; index < found.size(); ++index) {
    const FoundTag& tag = found[index];
    const bool on_truth = truth && QuadIoU(tag.corners, truth->corners) >= min_iou;
    const bool matches = on_truth && tag.id == truth->id && tag.family == truth->family;
    if (matches && !score.found) {
      score.found = true;
      score.found_index = static_cast<int>(index);
      const Quad& t = truth->corners;
      const cv::Point2d centre = (t[0] + t[1] + t[2] + t[3]) / 4.0;
      cv::Point2d sum;
      for (int c = 0; c < 4; ++c) {
        const cv::Point2d delta = tag.corners[c] - t[c];
        score.corner_error_px[c] = std::hypot(delta.x, delta.y);
        sum += delta;
        const cv::Point2d outwards = t[c] - centre;
        const double length = std::hypot(outwards.x, outwards.y);
        if (length > 0) score.mean_radial_offset_px += delta.dot(outwards) / length / 4.0;
      }
      score.mean_offset_px = sum / 4.0;
      if (tag.has_inner_corners) {
        const auto family = TagFamily::Load(truth->family);
        const std::vector<cv::Point2f> unit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        const std::vector<cv::Point2f> square(t.begin(), t.end());
        const cv::Matx33d h(cv::getPerspectiveTransform(unit, square));
        for (int ring = 1; ring <= 2; ++ring) {
          const double in = static_cast<double>(ring) / family->black_square_cells();
          const double corner[4][2] = {{in, in}, {1 - in, in}, {1 - in, 1 - in}, {in, 1 - in}};
          for (int c = 0; c < 4; ++c) {
            const cv::Vec3d p = h * cv::Vec3d(corner[c][0], corner[c][1], 1.0);
            const cv::Point2d delta =
                tag.inner_corners[4 * (ring - 1) + c] - cv::Point2d(p[0] / p[2], p[1] / p[2]);
            score.inner_corner_error_px.push_back(std::hypot(delta.x, delta.y));
          }
        }
      }
      continue;
    }
    ++score.false_positives;
    if (on_truth && !matches) ++score.wrong_ids;
    if (matches) ++score.duplicates;  // The tag was found already.
    if (other && QuadIoU(tag.corners, other->corners) >= min_iou) ++score.false_on_other_tag;
  }
  return score;
}

void PoseError(const PoseEstimate& pose, const TagTruth& truth, double* rotation_deg,
               double* translation_pct) {
  cv::Vec3d apart;
  cv::Rodrigues(cv::Matx33d(pose.rotation.t() * truth.rotation), apart);
  *rotation_deg = cv::norm(apart) * 180.0 / kPi;
  *translation_pct =
      100.0 * cv::norm(pose.translation - truth.translation) / cv::norm(truth.translation);
}

bool PoseNormalisedError(const PoseEstimate& pose, const TagTruth& truth, std::array<double, 6>* z,
                         double* nees) {
  return pose.has_covariance &&
         PoseNormalisedError(pose.rotation, pose.translation, pose.covariance, truth.rotation,
                             truth.translation, z, nees);
}

bool PoseNormalisedError(const cv::Matx33d& rotation, const cv::Vec3d& translation,
                         const cv::Matx66d& covariance, const cv::Matx33d& true_rotation,
                         const cv::Vec3d& true_translation, std::array<double, 6>* z,
                         double* nees) {
  cv::Vec3d w;
  cv::Rodrigues(cv::Matx33d(true_rotation * rotation.t()), w);
  const cv::Vec3d t = true_translation - translation;
  const cv::Vec6d error(t[0], t[1], t[2], w[0], w[1], w[2]);
  cv::Matx66d inverse;
  if (cv::invert(covariance, inverse, cv::DECOMP_CHOLESKY) == 0.0) return false;
  for (int i = 0; i < 6; ++i) (*z)[i] = error[i] / std::sqrt(covariance(i, i));
  *nees = (error.t() * inverse * error)[0];
  return std::isfinite(*nees);
}

void CovarianceTally::Add(const std::array<double, 6>& z, double nees) {
  for (int i = 0; i < 6; ++i) squares_[i] += z[i] * z[i];
  inside_ += nees <= kChiSquare6At95;
  ++poses_;
}

double CovarianceTally::Spread(int axis) const {
  return poses_ ? std::sqrt(squares_[axis] / poses_) : kNaN;
}

double CovarianceTally::Coverage() const {
  return poses_ ? static_cast<double>(inside_) / poses_ : kNaN;
}

double Percentile(std::vector<double> values, double p) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * (values.size() - 1);
  const size_t below = static_cast<size_t>(std::floor(rank));
  const size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (rank - below) * (values[above] - values[below]);
}

int Bins::Index(double value) const {
  const int i = static_cast<int>(std::floor((value - lo) / width));
  return std::clamp(i, 0, count - 1);
}

void RecallCurve::Add(double value, bool hit) {
  const int i = bins.Index(value);
  ++trials[i];
  hits[i] += hit ? 1 : 0;
}

double RecallCurve::Recall(int index) const {
  return trials[index] > 0 ? static_cast<double>(hits[index]) / trials[index] : kNaN;
}

RecallMap::RecallMap(const Bins& x_bins, const Bins& y_bins)
    : x_bins(x_bins),
      y_bins(y_bins),
      hits(static_cast<size_t>(x_bins.count) * y_bins.count),
      trials(hits.size()) {}

void RecallMap::Add(double x, double y, bool hit) {
  const size_t i = static_cast<size_t>(y_bins.Index(y)) * x_bins.count + x_bins.Index(x);
  ++trials[i];
  hits[i] += hit ? 1 : 0;
}

double RecallMap::Recall(int x_index, int y_index) const {
  const size_t i = static_cast<size_t>(y_index) * x_bins.count + x_index;
  return trials[i] > 0 ? static_cast<double>(hits[i]) / trials[i] : kNaN;
}

int RecallMap::Trials(int x_index, int y_index) const {
  return trials[static_cast<size_t>(y_index) * x_bins.count + x_index];
}

}  // namespace chromatag::bench
