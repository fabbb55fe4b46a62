// Scoring detections against the ground truth as in the paper (section 5.2):
// a true positive has the right family and ID and an intersection over union
// of at least 0.5 with the true black square; every other detection is a false positive;
// a tag not found is a false negative.
#ifndef CHROMATAG_BENCH_METRICS_H_
#define CHROMATAG_BENCH_METRICS_H_

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/bench/competitors.h"
#include "chromatag/bench/dataset.h"

namespace chromatag::bench {

using Quad = std::array<cv::Point2d, 4>;

// Area of intersection over area of union of two simple quadrilaterals (any
// winding; convex or not). 0 when either is degenerate.
double QuadIoU(const Quad& a, const Quad& b);

struct FrameScore {
  bool found = false;          // The tag was detected (a true positive)...
  int found_index = -1;        // ...as this entry of the detections.
  int false_positives = 0;     // Wrong ID, wrong place, or a second report of the tag.
  int false_on_other_tag = 0;  // Of those, how many lie on the frame's other tag.
  int wrong_ids = 0;           // Of those, how many lie on the own tag with a wrong family or ID.
  int duplicates = 0;          // Of those, how many are the own tag again, right family and ID.
  // When found: each corner's distance to the truth, pixels, and the mean
  // signed offset (detected minus true), which shows a convention mismatch.
  std::array<double, 4> corner_error_px{};
  cv::Point2d mean_offset_px;
  // Mean offset along the direction from the true centre to each true
  // corner: negative when the square is found too small.
  double mean_radial_offset_px = 0.0;
  // For a detector reporting inner ring corners (FoundTag::inner_corners):
  // each one's distance to where the true black square's homography puts
  // it (the data sets' tags are plane projections).
  std::vector<double> inner_corner_error_px;
};

// Scores one detector's output on one frame. `truth` is the tag this
// detector should find (nullptr for a tag-free frame); `other` the tag of the
// other kind beside it (nullptr if none).
FrameScore ScoreFrame(const std::vector<FoundTag>& found, const TagTruth* truth,
                      const TagTruth* other, double min_iou = 0.5);

// `pose` of the tag whose truth is `truth` (TagTruth::rotation and
// translation): the angle of the rotation between them, degrees, and the
// distance between the translations in % of the true distance.
void PoseError(const PoseEstimate& pose, const TagTruth& truth, double* rotation_deg,
               double* translation_pct);

// `pose`'s error against the truth in its covariance's terms: per axis
// (translation x, y, z, then the rotation w with R_truth = exp([w]x) R),
// truth minus estimate over the predicted standard deviation, into *z; and
// the squared Mahalanobis distance of the whole error (chi-square with six
// degrees of freedom when the covariance is right) into *nees. False when
// the pose has no covariance or it is not positive definite.
bool PoseNormalisedError(const PoseEstimate& pose, const TagTruth& truth, std::array<double, 6>* z,
                         double* nees);
// The same for any pose (rotation, translation, covariance in TagPose's
// terms) against a true rotation and translation.
bool PoseNormalisedError(const cv::Matx33d& rotation, const cv::Vec3d& translation,
                         const cv::Matx66d& covariance, const cv::Matx33d& true_rotation,
                         const cv::Vec3d& true_translation, std::array<double, 6>* z, double* nees);

// The 95 % point of a chi-square with six degrees of freedom.
inline constexpr double kChiSquare6At95 = 12.5916;

// How well poses' covariances predicted their errors (PoseNormalisedError
// of each): per axis the root mean square of error over sigma (1 when the
// covariance is right), and the share of poses inside the 95 % ellipsoid.
class CovarianceTally {
 public:
  void Add(const std::array<double, 6>& z, double nees);
  int poses() const { return poses_; }
  double Spread(int axis) const;  // NaN without poses.
  double Coverage() const;        // NaN without poses.

 private:
  int poses_ = 0, inside_ = 0;
  std::array<double, 6> squares_{};
};

// p-th percentile (p in [0, 100]) with linear interpolation between order
// statistics; NaN for an empty sample. Takes a copy to sort.
double Percentile(std::vector<double> values, double p);

// Fixed-width bins over [lo, lo + count * width); values outside go to the
// end bins.
struct Bins {
  double lo = 0.0;
  double width = 1.0;
  int count = 1;
  int Index(double value) const;
  double Centre(int index) const { return lo + (index + 0.5) * width; }
  double Edge(int index) const { return lo + index * width; }
};

// Hits over trials per bin (recall against size or angle), and per cell of a
// two-dimensional grid.
struct RecallCurve {
  explicit RecallCurve(const Bins& bins) : bins(bins), hits(bins.count), trials(bins.count) {}
  void Add(double value, bool hit);
  double Recall(int index) const;  // NaN without trials.
  Bins bins;
  std::vector<int> hits, trials;
};

struct RecallMap {
  RecallMap(const Bins& x_bins, const Bins& y_bins);
  void Add(double x, double y, bool hit);
  double Recall(int x_index, int y_index) const;  // NaN without trials.
  int Trials(int x_index, int y_index) const;
  Bins x_bins, y_bins;
  std::vector<int> hits, trials;  // Row-major, y rows.
};

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_METRICS_H_
