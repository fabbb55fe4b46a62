#include "chromatag/bench/competitors.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag36h11.h>

#include <opencv2/aruco.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/detector.h"

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
  DetectionResult result, analysis;
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
  impl->detector = Detector::Create(options, error);
  if (!impl->detector) return nullptr;
  options.report_rejected = true;
  impl->reporting = Detector::Create(options, error);
  if (!impl->reporting) return nullptr;
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
    found->push_back(tag);
  }
}

const DetectorSummary& ChromaTagDetector::last_summary() const { return impl_->result.summary; }

MissCause ChromaTagDetector::ExplainMiss(const cv::Mat& bgr, const FrameTruth& truth) {
  impl_->reporting->Detect(bgr, PixelOrder::kBgr, &impl_->analysis);
  const auto family = TagFamily::Load(truth.family);
  CV_Assert(truth.has_tags && family);
  return AssignMiss(impl_->analysis, truth.chromatag, family->black_square_cells(),
                    truth.quiet_zone_cells);
}

}  // namespace chromatag::bench
