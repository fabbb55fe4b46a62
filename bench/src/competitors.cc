#include "chromatag/bench/competitors.h"

#include <cstdlib>

#include <apriltag/apriltag.h>
#include <apriltag/apriltag_pose.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag36h11.h>

#include <opencv2/aruco.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/corner_bend.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/pose.h"

namespace chromatag::bench {
namespace {

// Checks a list of family names: not empty, each known, none twice.
bool ValidFamilies(const std::vector<std::string>& families, std::string* error) {
  std::string why;
  if (families.empty()) why = "no family given (allowed: 16h5, 36h11)";
  for (size_t i = 0; i < families.size() && why.empty(); ++i) {
    if (families[i] != "16h5" && families[i] != "36h11") {
      why = "unknown family '" + families[i] + "' (allowed: 16h5, 36h11)";
    }
    for (size_t j = 0; j < i && why.empty(); ++j) {
      if (families[j] == families[i]) why = "family " + families[i] + " given twice";
    }
  }
  if (error) *error = why;
  return why.empty();
}

class AprilTag final : public TagDetector {
 public:
  explicit AprilTag(const std::vector<std::string>& families)
      : detector_(apriltag_detector_create()) {
    for (const std::string& name : families) {
      apriltag_family_t* family = name == "16h5" ? tag16h5_create() : tag36h11_create();
      families_.push_back({family, name});
      apriltag_detector_add_family(detector_, family);
    }
    detector_->nthreads = 1;
  }
  ~AprilTag() override {
    apriltag_detector_destroy(detector_);
    for (const auto& [family, name] : families_) {
      if (name == "16h5") {
        tag16h5_destroy(family);
      } else {
        tag36h11_destroy(family);
      }
    }
  }
  AprilTag(const AprilTag&) = delete;
  AprilTag& operator=(const AprilTag&) = delete;

  const std::string& name() const override { return name_; }

  // libapriltag's estimate_tag_pose (apriltag_pose.h: homography, then
  // orthogonal iteration from both its solutions), in AprilTag's pixel
  // convention; its tag frame (x right, y down, z into the tag) turned half
  // a turn about x into the spec's.
  bool Pose(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
            PoseEstimate* pose) const override {
    // Debian's libapriltag exports none of the matd functions: a matd_t is
    // one calloc'd block (its header's struct with the data after it), so
    // one is made and freed here the same way.
    apriltag_detection_t detection{};
    detection.H = static_cast<matd_t*>(std::calloc(1, sizeof(matd_t) + 9 * sizeof(double)));
    if (!detection.H) return false;
    detection.H->nrows = detection.H->ncols = 3;
    std::copy(tag.apriltag_h.begin(), tag.apriltag_h.end(), detection.H->data);
    for (int c = 0; c < 4; ++c) {
      const int i = kAprilTagCornerOrder[c];
      detection.p[i][0] = tag.corners[c].x + kAprilTagPixelCentre;
      detection.p[i][1] = tag.corners[c].y + kAprilTagPixelCentre;
    }
    detection.c[0] = detection.H->data[2] / detection.H->data[8];
    detection.c[1] = detection.H->data[5] / detection.H->data[8];
    apriltag_detection_info_t info{&detection,
                                   tag_size,
                                   k(0, 0),
                                   k(1, 1),
                                   k(0, 2) + kAprilTagPixelCentre,
                                   k(1, 2) + kAprilTagPixelCentre};
    apriltag_pose_t result{};
    estimate_tag_pose(&info, &result);
    std::free(detection.H);
    if (!result.R || !result.t) {
      std::free(result.R);
      std::free(result.t);
      return false;
    }
    cv::Matx33d r;
    for (int i = 0; i < 9; ++i) r.val[i] = result.R->data[i];
    pose->rotation = r * cv::Matx33d(1, 0, 0, 0, -1, 0, 0, 0, -1);
    pose->translation = cv::Vec3d(result.t->data[0], result.t->data[1], result.t->data[2]);
    std::free(result.R);
    std::free(result.t);
    return true;
  }

  void Detect(const cv::Mat& bgr, std::vector<FoundTag>* found) override {
    found->clear();
    cv::cvtColor(bgr, gray_, cv::COLOR_BGR2GRAY);
    image_u8_t image{gray_.cols, gray_.rows, static_cast<int32_t>(gray_.step), gray_.data};
    zarray_t* detections = apriltag_detector_detect(detector_, &image);
    for (int i = 0; i < zarray_size(detections); ++i) {
      apriltag_detection_t* d = nullptr;
      zarray_get(detections, i, &d);
      FoundTag tag;
      tag.id = d->id;
      for (const auto& [family, name] : families_) {
        if (family == d->family) tag.family = name;
      }
      for (int c = 0; c < 4; ++c) {
        const int k = kAprilTagCornerOrder[c];
        tag.corners[c] = {d->p[k][0] - kAprilTagPixelCentre, d->p[k][1] - kAprilTagPixelCentre};
      }
      std::copy(d->H->data, d->H->data + 9, tag.apriltag_h.begin());
      found->push_back(tag);
    }
    apriltag_detections_destroy(detections);
  }

 private:
  const std::string name_ = "AprilTag 3";
  std::vector<std::pair<apriltag_family_t*, std::string>> families_;
  apriltag_detector_t* detector_;
  cv::Mat gray_;
};

class Aruco final : public TagDetector {
 public:
  explicit Aruco(const std::vector<std::string>& families)
      : parameters_(cv::aruco::DetectorParameters::create()) {
    for (const std::string& name : families) {
      dictionaries_.push_back(
          {cv::aruco::getPredefinedDictionary(name == "16h5" ? cv::aruco::DICT_APRILTAG_16h5
                                                             : cv::aruco::DICT_APRILTAG_36h11),
           name});
    }
  }

  const std::string& name() const override { return name_; }

  // ArUco has no multi-dictionary call in 4.6: one detectMarkers per family,
  // each converting the frame to grey again, as a user of it would.
  void Detect(const cv::Mat& bgr, std::vector<FoundTag>* found) override {
    found->clear();
    for (const auto& [dictionary, family] : dictionaries_) {
      corners_.clear();
      ids_.clear();
      cv::aruco::detectMarkers(bgr, dictionary, corners_, ids_, parameters_);
      for (size_t i = 0; i < ids_.size(); ++i) {
        FoundTag tag;
        tag.id = ids_[i];
        tag.family = family;
        for (int c = 0; c < 4; ++c) tag.corners[c] = corners_[i][kArucoCornerOrder[c]];
        found->push_back(tag);
      }
    }
  }

 private:
  const std::string name_ = "OpenCV ArUco";
  std::vector<std::pair<cv::Ptr<cv::aruco::Dictionary>, std::string>> dictionaries_;
  cv::Ptr<cv::aruco::DetectorParameters> parameters_;
  std::vector<std::vector<cv::Point2f>> corners_;
  std::vector<int> ids_;
};

}  // namespace

bool TagDetector::Pose(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
                       PoseEstimate* pose) const {
  const double h = 0.5 * tag_size;
  const std::vector<cv::Point3d> object = {{-h, h, 0}, {h, h, 0}, {h, -h, 0}, {-h, -h, 0}};
  const std::vector<cv::Point2d> image(tag.corners.begin(), tag.corners.end());
  cv::Mat rvec, tvec;
  if (!cv::solvePnP(object, image, k, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE_SQUARE))
    return false;
  cv::Rodrigues(rvec, pose->rotation);
  pose->translation = cv::Vec3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return true;
}

std::unique_ptr<TagDetector> MakeAprilTagDetector(const std::vector<std::string>& families,
                                                  std::string* error) {
  if (!ValidFamilies(families, error)) return nullptr;
  return std::make_unique<AprilTag>(families);
}

std::unique_ptr<TagDetector> MakeArucoDetector(const std::vector<std::string>& families,
                                               std::string* error) {
  if (!ValidFamilies(families, error)) return nullptr;
  return std::make_unique<Aruco>(families);
}

struct ChromaTagDetector::Impl {
  std::unique_ptr<Detector> detector;
  std::unique_ptr<Detector> reporting;  // The same, with report_rejected on.
  std::unique_ptr<Detector> staged;     // The same, with time_stages on.
  DetectionResult result, analysis, staged_result;
  const std::string name = "ChromaTag";
};

ChromaTagDetector::ChromaTagDetector(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ChromaTagDetector::~ChromaTagDetector() = default;

std::unique_ptr<ChromaTagDetector> ChromaTagDetector::Create(
    const std::vector<std::string>& families, std::string* error) {
  DetectorOptions options;
  options.families = families;
  return CreateWithOptions(options, error);
}

std::unique_ptr<ChromaTagDetector> ChromaTagDetector::CreateWithOptions(
    const DetectorOptions& given, std::string* error) {
  if (!ValidFamilies(given.families, error)) return nullptr;
  auto impl = std::make_unique<Impl>();
  DetectorOptions options = given;
  options.report_rejected = false;
  options.time_stages = false;
  impl->detector = Detector::Create(options, error);
  if (!impl->detector) return nullptr;
  options.report_rejected = true;
  impl->reporting = Detector::Create(options, error);
  if (!impl->reporting) return nullptr;
  options.report_rejected = false;
  options.time_stages = true;
  impl->staged = Detector::Create(options, error);
  if (!impl->staged) return nullptr;
  return std::unique_ptr<ChromaTagDetector>(new ChromaTagDetector(std::move(impl)));
}

const std::string& ChromaTagDetector::name() const { return impl_->name; }

void ChromaTagDetector::Detect(const cv::Mat& bgr, std::vector<FoundTag>* found) {
  found->clear();
  impl_->detector->Detect(bgr, PixelOrder::kBgr, &impl_->result);
  for (const Detection& d : impl_->result.detections) {
    FoundTag tag;
    tag.id = d.id;
    tag.corners = d.corners;
    if (d.family) tag.family = d.family->name();
    tag.has_inner_corners = true;
    std::copy(d.green_corners.begin(), d.green_corners.end(), tag.inner_corners.begin());
    std::copy(d.red_corners.begin(), d.red_corners.end(), tag.inner_corners.begin() + 4);
    tag.corner_covariance = d.corner_covariance;
    found->push_back(tag);
  }
}

namespace {

// EstimateTagPose on `tag`'s twelve ring corners and their covariance.
bool RingCornerPose(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
                    PoseEstimate* pose) {
  const auto family = TagFamily::Load(tag.family);
  if (!family || !tag.has_inner_corners) return false;
  Detection detection;
  detection.family = family.get();
  detection.id = tag.id;
  detection.corners = tag.corners;
  std::copy(tag.inner_corners.begin(), tag.inner_corners.begin() + 4,
            detection.green_corners.begin());
  std::copy(tag.inner_corners.begin() + 4, tag.inner_corners.end(), detection.red_corners.begin());
  detection.corner_covariance = tag.corner_covariance;
  CameraIntrinsics camera;
  camera.fx = k(0, 0);
  camera.fy = k(1, 1);
  camera.cx = k(0, 2);
  camera.cy = k(1, 2);
  TagPose estimate;
  if (!EstimateTagPose(detection, camera, tag_size, &estimate)) return false;
  cv::Rodrigues(estimate.rvec, pose->rotation);
  pose->translation = estimate.tvec;
  pose->has_covariance = true;
  pose->covariance = estimate.covariance;
  return true;
}

}  // namespace

bool ChromaTagDetector::Pose(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
                             PoseEstimate* pose) const {
  return RingCornerPose(tag, k, tag_size, pose);
}

bool AssumedPoseCovariance(const FoundTag& tag, const cv::Matx33d& k, double tag_size,
                           double sigma_px, cv::Matx66d* covariance) {
  // ChromaTag's 16h5 proportions place the inner corners: only the black
  // square's four carry information.
  FoundTag hand = tag;
  hand.family = "16h5";
  const double cell = 1.0 / TagFamily::Load(hand.family)->black_square_cells();
  std::vector<cv::Point2d> in_square;
  for (double inset : {cell, 2 * cell}) {
    for (const cv::Point2d& p : {cv::Point2d(inset, inset), cv::Point2d(1 - inset, inset),
                                 cv::Point2d(1 - inset, 1 - inset), cv::Point2d(inset, 1 - inset)})
      in_square.push_back(p);
  }
  const std::vector<cv::Point2d> inner = PlaceInnerCorners(tag.corners, in_square);
  std::copy(inner.begin(), inner.end(), hand.inner_corners.begin());
  hand.has_inner_corners = true;
  hand.corner_covariance = sigma_px * sigma_px * cv::Matx<double, 8, 8>::eye();
  PoseEstimate pose;
  if (!RingCornerPose(hand, k, tag_size, &pose)) return false;
  *covariance = pose.covariance;
  return true;
}

const DetectorSummary& ChromaTagDetector::last_summary() const { return impl_->result.summary; }

const DetectorSummary& ChromaTagDetector::TimeStages(const cv::Mat& bgr) {
  impl_->staged->Detect(bgr, PixelOrder::kBgr, &impl_->staged_result);
  return impl_->staged_result.summary;
}

MissCause ChromaTagDetector::ExplainMiss(const cv::Mat& bgr, const FrameTruth& truth) {
  impl_->reporting->Detect(bgr, PixelOrder::kBgr, &impl_->analysis);
  const auto family = TagFamily::Load(truth.family);
  CV_Assert(truth.has_tags && family);
  return AssignMiss(impl_->analysis, truth.chromatag, family->black_square_cells(),
                    truth.quiet_zone_cells);
}

}  // namespace chromatag::bench
