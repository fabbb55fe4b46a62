#include "chromatag/bench/competitors.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>

#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/detector.h"

namespace chromatag::bench {
namespace {

class AprilTag final : public TagDetector {
 public:
  AprilTag() : family_(tag16h5_create()), detector_(apriltag_detector_create()) {
    apriltag_detector_add_family(detector_, family_);
    detector_->nthreads = 1;
  }
  ~AprilTag() override {
    apriltag_detector_destroy(detector_);
    tag16h5_destroy(family_);
  }
  AprilTag(const AprilTag&) = delete;
  AprilTag& operator=(const AprilTag&) = delete;

  const std::string& name() const override { return name_; }

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
      for (int c = 0; c < 4; ++c) {
        const int k = kAprilTagCornerOrder[c];
        tag.corners[c] = {d->p[k][0] - kAprilTagPixelCentre, d->p[k][1] - kAprilTagPixelCentre};
      }
      found->push_back(tag);
    }
    apriltag_detections_destroy(detections);
  }

 private:
  const std::string name_ = "AprilTag 3";
  apriltag_family_t* family_;
  apriltag_detector_t* detector_;
  cv::Mat gray_;
};

class Aruco final : public TagDetector {
 public:
  Aruco()
      : dictionary_(cv::aruco::getPredefinedDictionary(cv::aruco::DICT_APRILTAG_16h5)),
        parameters_(cv::aruco::DetectorParameters::create()) {}

  const std::string& name() const override { return name_; }

  void Detect(const cv::Mat& bgr, std::vector<FoundTag>* found) override {
    found->clear();
    corners_.clear();
    ids_.clear();
    cv::aruco::detectMarkers(bgr, dictionary_, corners_, ids_, parameters_);
    for (size_t i = 0; i < ids_.size(); ++i) {
      FoundTag tag;
      tag.id = ids_[i];
      for (int c = 0; c < 4; ++c) tag.corners[c] = corners_[i][kArucoCornerOrder[c]];
      found->push_back(tag);
    }
  }

 private:
  const std::string name_ = "OpenCV ArUco";
  cv::Ptr<cv::aruco::Dictionary> dictionary_;
  cv::Ptr<cv::aruco::DetectorParameters> parameters_;
  std::vector<std::vector<cv::Point2f>> corners_;
  std::vector<int> ids_;
};

}  // namespace

std::unique_ptr<TagDetector> MakeAprilTagDetector() { return std::make_unique<AprilTag>(); }
std::unique_ptr<TagDetector> MakeArucoDetector() { return std::make_unique<Aruco>(); }

struct ChromaTagDetector::Impl {
  std::unique_ptr<Detector> detector;
  DetectionResult result;
  const std::string name = "ChromaTag";
};

ChromaTagDetector::ChromaTagDetector(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
ChromaTagDetector::~ChromaTagDetector() = default;

std::unique_ptr<ChromaTagDetector> ChromaTagDetector::Create(std::string* error) {
  auto impl = std::make_unique<Impl>();
  DetectorOptions options;
  options.families = {"16h5"};
  impl->detector = Detector::Create(options, error);
  if (!impl->detector) return nullptr;
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
    found->push_back(tag);
  }
}

const DetectorSummary& ChromaTagDetector::last_summary() const { return impl_->result.summary; }

}  // namespace chromatag::bench
