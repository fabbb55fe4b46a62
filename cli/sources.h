// The inputs of `detect` and `calibrate-camera`: images, folders of them,
// videos, /dev/videoN, stream URLs and camera indices, in order.
#ifndef CHROMATAG_CLI_SOURCES_H_
#define CHROMATAG_CLI_SOURCES_H_

#include <filesystem>
#include <opencv2/videoio.hpp>
#include <string>
#include <vector>

namespace chromatag::cli {

// By extension.
bool IsVideo(const std::filesystem::path& path);
bool IsImage(const std::filesystem::path& path);

enum class SourceKind { kImage, kVideo, kCamera, kStream };

struct Source {
  SourceKind kind = SourceKind::kImage;
  std::string name;  // As given: a path, /dev/videoN, "camera N" or a URL.
  int camera_index = -1;
  std::string overlay_stem;  // Unique among the run's sources.
  bool live() const { return kind == SourceKind::kCamera || kind == SourceKind::kStream; }
};

// The default of --open-timeout: how long a stream may take to answer.
inline constexpr double kDefaultOpenTimeout = 10.0;

// Opens `source` (a video, a camera or a stream) into *capture; a stream
// through FFmpeg with `open_timeout_s` for its server to answer (FFmpeg's own
// wait is 30 s or more). False when it does not open.
bool OpenSource(const Source& source, double open_timeout_s, cv::VideoCapture* capture);

// The sources named on the command line (a folder gives its images and
// videos, sorted; its subfolders are named in *notes, not read; entries it
// cannot read, such as a symbolic link loop, in *skipped), then the camera
// indices; false with *error for inputs that do not exist (a /dev/videoN
// too) or are not regular files, a negative camera index, or no input at all.
bool GatherSources(const std::vector<std::string>& inputs, const std::vector<int>& camera_indices,
                   std::vector<Source>* sources, std::string* error,
                   std::vector<std::string>* notes = nullptr,
                   std::vector<std::string>* skipped = nullptr);

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_SOURCES_H_
