// ChromaTag detection: the paper's Algorithm 1 (section 4).
//
//   Detector::Create(options) -> Detect(frame) -> detections + summary.
//
// Thread safety: a Detector's options and tables are fixed at Create.
// Detect() is const and may be called from several threads at once on
// different frames; each call borrows scratch memory from the detector's pool
// (one set per call in flight, kept for the next). The detector never writes
// into the caller's image.
#ifndef CHROMATAG_DETECTOR_DETECTOR_H_
#define CHROMATAG_DETECTOR_DETECTOR_H_

#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"

namespace chromatag {

namespace internal {
struct DetectorAccess;
}  // namespace internal

// Channel order of a 3-channel 8-bit frame: OpenCV's imread gives BGR.
enum class PixelOrder { kBgr, kRgb };

class Detector {
 public:
  // Loads the families and builds the decoders and colour conversions. Returns
  // nullptr and sets *error for options that fail DetectorOptions::IsValid.
  static std::unique_ptr<Detector> Create(const DetectorOptions& options,
                                          std::string* error = nullptr);
  ~Detector();

  // Detects every tag in `image`: CV_8UC3, any size, ROIs and padded rows
  // allowed. Any other type gives an empty result. `result` is overwritten; passing the
  // same one frame after frame reuses its memory.
  void Detect(const cv::Mat& image, PixelOrder order, DetectionResult* result) const;
  DetectionResult Detect(const cv::Mat& image, PixelOrder order = PixelOrder::kBgr) const;

  // The options it was created with; `families` named as the library names
  // them ("16h5" for "tag16h5"), each once.
  const DetectorOptions& options() const;

 private:
  friend struct internal::DetectorAccess;  // The benchmarks' stage switches.
  struct Impl;
  explicit Detector(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_DETECTOR_H_
