// Camera files: read_camera.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "chromatag/rig/camera_file.h"
#include "common.h"

namespace chromatag::python {
namespace {

// A camera file's intrinsics as OpenCV's Python functions take them.
py::dict ReadCamera(const std::filesystem::path& file) {
  const std::string path = file.string();
  CameraIntrinsics camera;
  CameraFileInfo info;
  std::string error;
  if (!LoadCameraFile(path, &camera, &error, &info)) throw Error(error);
  py::array_t<double> k({3, 3});
  auto m = k.mutable_unchecked<2>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = 0.0;
  m(0, 0) = camera.fx;
  m(1, 1) = camera.fy;
  m(0, 2) = camera.cx;
  m(1, 2) = camera.cy;
  m(2, 2) = 1.0;
  py::array_t<double> d(static_cast<py::ssize_t>(camera.distortion.size()));
  for (size_t i = 0; i < camera.distortion.size(); ++i)
    d.mutable_at(static_cast<py::ssize_t>(i)) = camera.distortion[i];
  py::dict out;
  out["camera_matrix"] = k;
  out["dist_coeffs"] = d;
  out["camera_model"] = LensModelName(camera.model);
  out["image_size"] =
      info.image_size.empty()
          ? py::object(py::none())
          : py::object(py::make_tuple(info.image_size.width, info.image_size.height));
  return out;
}

}  // namespace

void BindCalibration(py::module_& m) {
  m.def("read_camera", &ReadCamera, py::arg("path"),
        "A camera file's intrinsics (OpenCV, ROS camera_info or Kalibr YAML; OpenCV JSON or XML),\n"
        "as the CLI's --camera reads them: {'camera_matrix': 3x3, 'dist_coeffs', 'camera_model':\n"
        "'pinhole' or 'fisheye', 'image_size': (w, h) or None}.\n"
        "Detector(camera_file=path) takes the same file.");
}

}  // namespace chromatag::python
