// Camera files: intrinsics in the layouts people feed to their tools, read
// for `detect --camera FILE` and written by `calibrate-camera`.
//
// - OpenCV's calibration output (camera_matrix, distortion_coefficients) as
//   YAML, JSON or XML (cv::FileStorage's layouts); a `distortion_model` of
//   "fisheye" (or "equidistant") marks cv::fisheye's model;
// - ROS camera_info YAML (camera_calibration's ost.yaml: camera_matrix and
//   distortion_coefficients as {rows, cols, data}, distortion_model
//   plumb_bob, rational_polynomial or equidistant);
// - Kalibr's camchain YAML (cam0: camera_model pinhole, intrinsics
//   [fu, fv, pu, pv], distortion_model radtan, equidistant or none,
//   distortion_coeffs).
//
// Parsed here (yaml-cpp, nlohmann-json, and the two matrices of OpenCV's
// XML read directly), never by cv::FileStorage, which crashed on truncated
// XML; files over 1 MiB or not regular files are refused.
#ifndef CHROMATAG_RIG_CAMERA_FILE_H_
#define CHROMATAG_RIG_CAMERA_FILE_H_

#include <string>

#include <opencv2/core.hpp>

#include "chromatag/detector/options.h"

namespace chromatag {

enum class CameraFileFormat {
  kOpenCv,  // cv::FileStorage YAML, as OpenCV's calibration samples write it.
  kRos,     // ROS camera_info YAML (camera_calibration's ost.yaml).
  kKalibr,  // Kalibr camchain YAML, one camera (cam0).
};

// "opencv", "ros", "kalibr".
const char* CameraFileFormatName(CameraFileFormat format);

// What a camera file says besides the intrinsics.
struct CameraFileInfo {
  cv::Size image_size;
  std::string camera_name = "camera";  // ROS camera_name; Kalibr's rostopic is /<name>/image_raw.
  double rms_px = -1.0;                // Reprojection rms of the calibration; < 0: not written.
};

// False with *error naming the file and what was wrong or missing. *info,
// when given, gets the image size the file records ((0, 0) if none; the
// other fields keep their defaults).
bool LoadCameraFile(const std::string& path, CameraIntrinsics* camera, std::string* error,
                    CameraFileInfo* info = nullptr);

// The same from the file's text and extension (".yaml", ".json", ".xml");
// *why says what was wrong, without the file's name.
bool ParseCameraFile(const std::string& text, const std::string& extension,
                     CameraIntrinsics* camera, std::string* why, CameraFileInfo* info = nullptr);

// The file's text; empty with *error when the format cannot hold the camera
// (Kalibr's radtan has no k3 to k6; ROS's equidistant and Kalibr's have
// exactly four coefficients).
std::string CameraFileText(const CameraIntrinsics& camera, const CameraFileInfo& info,
                           CameraFileFormat format, std::string* error);

}  // namespace chromatag

#endif  // CHROMATAG_RIG_CAMERA_FILE_H_
