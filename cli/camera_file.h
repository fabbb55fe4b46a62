// Camera intrinsics for `detect --camera FILE`, from the files people have:
//
// - OpenCV's calibration output (camera_matrix, distortion_coefficients) as
//   YAML, JSON or XML (cv::FileStorage's layouts);
// - ROS camera_info YAML (camera_calibration's ost.yaml: camera_matrix and
//   distortion_coefficients as {rows, cols, data}, distortion_model
//   plumb_bob or rational_polynomial);
// - Kalibr's camchain YAML (cam0: intrinsics [fu, fv, pu, pv],
//   distortion_model radtan or none, distortion_coeffs).
//
// Parsed here (yaml-cpp, nlohmann-json, and the two matrices of OpenCV's
// XML read directly), never by cv::FileStorage, which crashed on truncated
// XML; files over 1 MiB or not regular files are refused.
#ifndef CHROMATAG_CLI_CAMERA_FILE_H_
#define CHROMATAG_CLI_CAMERA_FILE_H_

#include <string>

#include "chromatag/detector/options.h"

namespace chromatag::cli {

// False with *error naming the file and what was wrong or missing.
bool LoadCameraFile(const std::string& path, CameraIntrinsics* camera, std::string* error);

// The same from the file's text and extension (".yaml", ".json", ".xml");
// *why says what was wrong, without the file's name.
bool ParseCameraFile(const std::string& text, const std::string& extension,
                     CameraIntrinsics* camera, std::string* why);

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_CAMERA_FILE_H_
