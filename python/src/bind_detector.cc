// The detector's side of the module: Pose, Detection, Detector and
// draw_detections.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>

#include <nlohmann/json.hpp>

#include "chromatag/detector/config.h"
#include "chromatag/detector/detection_json.h"
#include "chromatag/detector/draw.h"
#include "chromatag/detector/pose.h"
#include "chromatag/rig/camera_file.h"
#include "common.h"

namespace chromatag::python {
namespace {

// The JSON value of a keyword argument, for ParseDetectorConfig.
nlohmann::json JsonOf(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>();
  if (py::isinstance<py::int_>(value))
    return Arg<long long>(value, "option " + name, "a number that fits in 64 bits");
  if (py::isinstance<py::float_>(value)) return value.cast<double>();
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    nlohmann::json list = nlohmann::json::array();
    for (const py::handle& item : value) list.push_back(JsonOf(name, item));
    return list;
  }
  throw Error("option " + name + ": cannot use a " +
              std::string(py::str(value.get_type().attr("__name__"))));
}

// Detector(...)'s keywords, sorted: the camera's and the few the config
// file does not hold; every other keyword is a config option (`fields`).
struct DetectorArgs {
  nlohmann::json fields = nlohmann::json::object();
  py::object camera_matrix = py::none(), dist_coeffs = py::none();
  double tag_size = 0.0;
  std::string config, camera_file, camera_model = "pinhole";
  bool model_given = false;
  bool report_rejected = false;
};

DetectorArgs SortArgs(const py::object& families, const py::kwargs& kwargs) {
  DetectorArgs args;
  if (py::isinstance<py::str>(families)) {
    args.fields["families"] = nlohmann::json::array({families.cast<std::string>()});
  } else {
    args.fields["families"] = JsonOf("families", families);
  }
  for (const auto& item : kwargs) {
    const std::string name = item.first.cast<std::string>();
    if (name == "camera_matrix") {
      args.camera_matrix = py::reinterpret_borrow<py::object>(item.second);
    } else if (name == "dist_coeffs") {
      args.dist_coeffs = py::reinterpret_borrow<py::object>(item.second);
    } else if (name == "camera_model") {
      args.camera_model = py::str(item.second);
      args.model_given = true;
    } else if (name == "camera_file") {
      args.camera_file = PathOrNone(item.second, "camera_file");
    } else if (name == "tag_size") {
      args.tag_size = Arg<double>(item.second, "tag_size", "a number (metres)");
    } else if (name == "report_rejected") {
      args.report_rejected = Arg<bool>(item.second, "report_rejected", "True or False");
    } else if (name == "config") {
      args.config = PathOrNone(item.second, "config");
    } else {
      args.fields[name] = JsonOf(name, item.second);
    }
  }
  return args;
}

// camera_matrix, dist_coeffs and camera_model as intrinsics.
CameraIntrinsics CameraFromMatrix(const DetectorArgs& args) {
  const std::string k_expected =
      "camera_matrix must be 3 x 3 ([[fx, 0, cx], [0, fy, cy], [0, 0, 1]])";
  const auto k = SmallNumbers(args.camera_matrix, 9, k_expected);
  if (k.ndim() != 2 || k.shape(0) != 3 || k.shape(1) != 3) throw Error(k_expected);
  CameraIntrinsics camera;
  std::string error;
  double matrix[9];
  for (int i = 0; i < 9; ++i) matrix[i] = k.at(i / 3, i % 3);
  if (!IntrinsicsFromMatrix(matrix, &camera, &error)) throw Error("camera_matrix: " + error);
  if (!args.dist_coeffs.is_none()) {
    const auto d = SmallNumbers(args.dist_coeffs, 64,
                                "dist_coeffs must be numbers (k1, k2, p1, p2[, k3[, k4, k5, "
                                "k6]])");
    for (py::ssize_t i = 0; i < d.size(); ++i) camera.distortion.push_back(d.data()[i]);
  }
  if (args.camera_model != "pinhole" && args.camera_model != "fisheye")
    throw Error("camera_model must be 'pinhole' or 'fisheye', not '" + args.camera_model + "'");
  camera.model = args.camera_model == "fisheye" ? LensModel::kFisheye : LensModel::kPinhole;
  if (!camera.IsValid(&error)) throw Error(error);
  return camera;
}

// The camera from camera_matrix or camera_file (not both), if either.
std::optional<CameraIntrinsics> CameraFromArgs(const DetectorArgs& args) {
  std::optional<CameraIntrinsics> camera;
  if (!args.camera_matrix.is_none()) {
    camera = CameraFromMatrix(args);
  } else if (!args.dist_coeffs.is_none()) {
    throw Error("dist_coeffs without camera_matrix");
  }
  if (!args.camera_file.empty()) {
    if (camera) throw Error("give camera_file or camera_matrix, not both");
    if (args.model_given) throw Error("camera_model comes from camera_file; give one or the other");
    CameraIntrinsics from_file;
    std::string error;
    if (!LoadCameraFile(args.camera_file, &from_file, &error)) throw Error(error);
    camera = from_file;
  }
  return camera;
}

// The config file first, then the keywords over it.
PyDetector MakeDetector(const py::object& families, const py::kwargs& kwargs) {
  const DetectorArgs args = SortArgs(families, kwargs);
  DetectorOptions options;
  options.families = {"16h5", "36h11"};
  std::string error;
  if (!args.config.empty() && !LoadDetectorConfig(args.config, &options, &error))
    throw Error(error);
  options.report_rejected = args.report_rejected;
  const nlohmann::json text = {
      {"schema", kDetectorConfigSchema}, {"schema_version", 1}, {"options", args.fields}};
  if (!ParseDetectorConfig(text.dump(), &options, &error)) throw Error(error);
  if (auto camera = CameraFromArgs(args)) options.camera = *camera;
  options.tag_size = args.tag_size;
  if (args.tag_size > 0 && !options.camera)
    throw Error("tag_size needs camera_matrix or camera_file for a pose");
  auto detector = Detector::Create(options, &error);
  if (!detector) throw Error(error);
  return {std::move(detector)};
}

// pupil-apriltags' call shape: the camera and tag size for one detect call.
struct CallPose {
  bool wanted = false;
  CameraIntrinsics camera;
  double tag_size = 0.0;
};

CallPose PoseForCall(bool estimate_tag_pose, const py::object& camera_params,
                     const py::object& tag_size) {
  CallPose pose;
  if (!estimate_tag_pose) {
    if (!camera_params.is_none() || !tag_size.is_none())
      throw Error("camera_params and tag_size are for estimate_tag_pose=True");
    return pose;
  }
  if (camera_params.is_none() || tag_size.is_none())
    throw Error("estimate_tag_pose needs camera_params=(fx, fy, cx, cy) and tag_size (metres)");
  const auto k = Arg<std::vector<double>>(camera_params, "camera_params", "(fx, fy, cx, cy)");
  if (k.size() != 4) throw Error("camera_params must be (fx, fy, cx, cy)");
  pose.wanted = true;
  pose.camera.fx = k[0];
  pose.camera.fy = k[1];
  pose.camera.cx = k[2];
  pose.camera.cy = k[3];
  pose.tag_size = Arg<double>(tag_size, "tag_size", "a number (metres)");
  std::string error;
  if (!pose.camera.IsValid(&error)) throw Error("camera_params: " + error);
  if (!(pose.tag_size > 0) || !std::isfinite(pose.tag_size))
    throw Error("tag_size must be a positive length, metres");
  return pose;
}

// For the first frames of a Detector without a tag: how many tags the other
// channel order finds, once per Detector (0 otherwise). Without the GIL.
size_t TagsInOtherOrder(const PyDetector& self, const cv::Mat& mat, PixelOrder order,
                        const DetectionResult& result) {
  PyDetector::OrderCheck& check = *self.order_check;
  if (!result.detections.empty() || check.left.load() <= 0 || check.left.fetch_sub(1) <= 0)
    return 0;
  const PixelOrder other = order == PixelOrder::kBgr ? PixelOrder::kRgb : PixelOrder::kBgr;
  const size_t found = self.detector->Detect(mat, other).detections.size();
  if (found == 0) return 0;
  check.left = 0;
  return check.warned.exchange(true) ? 0 : found;
}

void WarnOrder(PixelOrder order, size_t swapped_found) {
  const std::string given = order == PixelOrder::kBgr ? "bgr" : "rgb";
  const std::string other = order == PixelOrder::kBgr ? "rgb" : "bgr";
  const std::string message =
      "chromatag: no tag found with order='" + given + "', but " + std::to_string(swapped_found) +
      " with order='" + other + "': this image's red and blue look swapped (cv2.imread gives " +
      "BGR; PIL, imageio and most camera libraries give RGB). Pass order='" + other + "'.";
  if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) != 0) throw py::error_already_set();
}

// The rejected candidates as dicts (return_rejected=True).
py::list RejectedList(const std::vector<RejectedCandidate>& rejected) {
  py::list out;
  for (const RejectedCandidate& r : rejected) {
    py::dict entry;
    entry["stage"] = StageName(r.stage);
    entry["reason"] = RejectReasonName(r.reason);
    entry["seed"] = py::make_tuple(r.seed.x, r.seed.y);
    entry["centre"] = py::make_tuple(r.centre.x, r.centre.y);
    py::array_t<double> outline({static_cast<py::ssize_t>(r.outline.size()), py::ssize_t{2}});
    auto view = outline.mutable_unchecked<2>();
    for (size_t i = 0; i < r.outline.size(); ++i) {
      view(i, 0) = r.outline[i].x;
      view(i, 1) = r.outline[i].y;
    }
    entry["outline"] = outline;
    out.append(entry);
  }
  return out;
}

py::object Detect(const PyDetector& self, const py::object& image, const std::string& order,
                  bool return_rejected, bool estimate_tag_pose, const py::object& camera_params,
                  const py::object& tag_size) {
  const CallPose call = PoseForCall(estimate_tag_pose, camera_params, tag_size);
  py::object keep;
  const cv::Mat mat = ColourImage(image, &keep);
  const PixelOrder pixel_order = OrderFrom(order);
  DetectionResult result;
  size_t swapped_found = 0;
  {
    py::gil_scoped_release release;
    self.detector->Detect(mat, pixel_order, &result);
    if (call.wanted) {
      for (Detection& d : result.detections)
        d.has_pose = EstimateTagPose(d, call.camera, call.tag_size, &d.pose);
    }
    swapped_found = TagsInOtherOrder(self, mat, pixel_order, result);
  }
  if (swapped_found > 0) WarnOrder(pixel_order, swapped_found);
  py::list detections;
  for (Detection& d : result.detections) detections.append(PyDetection{std::move(d)});
  if (!return_rejected) return std::move(detections);
  return py::make_tuple(detections, RejectedList(result.rejected));
}

py::array DrawOn(py::array image, const std::vector<PyDetection>& detections,
                 const PyDetector* detector) {
  if (!(image.flags() & py::array::c_style) || !image.writeable())
    throw Error("draw_detections draws in place: give it a writeable, C-contiguous image");
  py::object keep;
  cv::Mat mat = ColourImage(image, &keep);
  if (mat.data != image.data()) throw Error("draw_detections needs an H x W x 3 uint8 image");
  std::vector<Detection> plain;
  for (const PyDetection& d : detections) plain.push_back(d.d);
  const DetectorOptions* options = detector ? &detector->detector->options() : nullptr;
  const CameraIntrinsics* camera = options && options->camera ? &*options->camera : nullptr;
  DrawDetections(plain, camera, options ? options->tag_size : 0.0, &mat);
  return image;
}

py::array DrawBoardOn(py::array image, const PyBoardPose& pose, const PyDetector& detector,
                      double axis_length, const std::string& name) {
  if (!(image.flags() & py::array::c_style) || !image.writeable())
    throw Error("draw_board_pose draws in place: give it a writeable, C-contiguous image");
  const DetectorOptions& options = detector.detector->options();
  if (!options.camera) throw Error("draw_board_pose needs the Detector built with camera_matrix");
  if (!(axis_length > 0)) throw Error("axis_length must be a positive length, metres");
  py::object keep;
  cv::Mat mat = ColourImage(image, &keep);
  if (mat.data != image.data()) throw Error("draw_board_pose needs an H x W x 3 uint8 image");
  DrawBoardPose(pose.pose, name, *options.camera, axis_length, &mat);
  return image;
}

// A Detection as `chromatag detect --json` writes it: the detector's one
// JSON writer, parsed into Python objects.
py::object DetectionDict(const PyDetection& detection) {
  return py::module_::import("json").attr("loads")(DetectionJson(detection.d));
}

// A pickled Detection's numbers: corners, homography, pose, errors and
// margin, then the pose's and the corners' covariances (pickles written
// before the covariances stop at the margin; they load with zeros).
constexpr size_t kStateNumbersWithoutCovariance = 24 + 9 + 6 + 3;
constexpr size_t kStateNumbers = kStateNumbersWithoutCovariance + 36 + 64;

// Every field of a Detection, for pickling: the family by name.
py::tuple DetectionState(const Detection& d) {
  std::vector<double> numbers;
  for (const auto* ring : {&d.corners, &d.green_corners, &d.red_corners})
    for (const cv::Point2d& p : *ring) numbers.insert(numbers.end(), {p.x, p.y});
  for (int i = 0; i < 9; ++i) numbers.push_back(d.image_from_tag.val[i]);
  for (int i = 0; i < 3; ++i) numbers.insert(numbers.end(), {d.pose.rvec[i], d.pose.tvec[i]});
  numbers.insert(numbers.end(), {d.pose.rms_error_px, d.pose.ambiguity, d.decision_margin});
  numbers.insert(numbers.end(), d.pose.covariance.val, d.pose.covariance.val + 36);
  numbers.insert(numbers.end(), d.corner_covariance.val, d.corner_covariance.val + 64);
  return py::make_tuple(d.family->name(), d.id, d.hamming, d.has_pose, numbers);
}

Detection DetectionFromState(const py::tuple& state) {
  const char* bad = "not a pickled chromatag.Detection";
  if (state.size() != 5) throw Error(bad);
  Detection d;
  std::vector<double> numbers;
  try {
    const auto family = TagFamily::Load(state[0].cast<std::string>());
    if (!family) throw Error(std::string(bad) + " (unknown family)");
    d.family = family.get();
    d.id = state[1].cast<int>();
    d.hamming = state[2].cast<int>();
    d.has_pose = state[3].cast<bool>();
    numbers = state[4].cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw Error(bad);
  }
  if (d.id < 0 || d.id >= d.family->num_apriltag_ids() || d.hamming < 0 ||
      (numbers.size() != kStateNumbers && numbers.size() != kStateNumbersWithoutCovariance) ||
      !std::all_of(numbers.begin(), numbers.end(), [](double x) { return std::isfinite(x); }))
    throw Error(bad);
  size_t k = 0;
  for (auto* ring : {&d.corners, &d.green_corners, &d.red_corners}) {
    for (cv::Point2d& p : *ring) {
      p.x = numbers[k++];
      p.y = numbers[k++];
    }
  }
  for (int i = 0; i < 9; ++i) d.image_from_tag.val[i] = numbers[k++];
  for (int i = 0; i < 3; ++i) {
    d.pose.rvec[i] = numbers[k++];
    d.pose.tvec[i] = numbers[k++];
  }
  d.pose.rms_error_px = numbers[k++];
  d.pose.ambiguity = numbers[k++];
  d.decision_margin = numbers[k++];
  if (numbers.size() == kStateNumbers) {
    for (double& v : d.pose.covariance.val) v = numbers[k++];
    for (double& v : d.corner_covariance.val) v = numbers[k++];
  }
  return d;
}

void BindPose(py::module_& m) {
  py::class_<TagPose>(m, "Pose", "A tag's pose in the camera frame (metres)")
      .def_property_readonly(
          "rvec", [](const TagPose& p) { return Vector(p.rvec.val, 3); },
          "Rodrigues rotation of camera_from_tag")
      .def_property_readonly(
          "tvec", [](const TagPose& p) { return Vector(p.tvec.val, 3); },
          "the tag's centre in the camera frame")
      .def_property_readonly(
          "rotation", [](const TagPose& p) { return RotationMatrix(p.rvec); },
          "3 x 3 rotation matrix of camera_from_tag (rvec as a matrix); the tag frame: x\n"
          "right, y up, z out of the tag, origin at its centre")
      .def_readonly("rms_error_px", &TagPose::rms_error_px,
                    "root mean square reprojection error over the twelve ring corners, pixels")
      .def_readonly("ambiguity", &TagPose::ambiguity,
                    "the kept planar solution's error over the other's: near 0 settled, near 1 "
                    "ambiguous (the tilt may be mirrored)")
      .def_property_readonly(
          "covariance", [](const TagPose& p) { return SquareMatrix(p.covariance.val, 6); },
          "6 x 6 covariance in ROS's PoseWithCovariance order: x, y, z (metres), then a small\n"
          "rotation about the camera's x, y, z axes composed onto the pose (radians)")
      .def("__repr__", [](const TagPose& p) {
        return "Pose(tvec=[" + std::to_string(p.tvec[0]) + ", " + std::to_string(p.tvec[1]) + ", " +
               std::to_string(p.tvec[2]) + "])";
      });
}

// Detection's fields; BindDetections adds its protocols.
py::class_<PyDetection> DetectionFields(py::module_& m) {
  return py::class_<PyDetection>(
             m, "Detection",
             "One tag found in an image: its family and ID, how sure the decoding is,\n"
             "its corners and, from a Detector with a camera and tag size, its pose.\n"
             "Compared by value, hashable, picklable; as_dict() gives the CLI's JSON.")
      .def_property_readonly(
          "family", [](const PyDetection& d) { return d.d.family->name(); },
          "the family's name: '16h5' or '36h11'")
      .def_property_readonly(
          "id", [](const PyDetection& d) { return d.d.id; }, "the tag's ID in its family")
      .def_property_readonly(
          "hamming", [](const PyDetection& d) { return d.d.hamming; }, "bits corrected")
      .def_property_readonly(
          "decision_margin", [](const PyDetection& d) { return d.d.decision_margin; },
          "how clearly the two shades split: the smaller gap between the two b* clusters over\n"
          "their pooled spread, for both colours (dimensionless; the CLI's JSON calls it\n"
          "'margin'). Low values mean a doubtful read")
      .def_property_readonly(
          "corners", [](const PyDetection& d) { return Points(d.d.corners.data(), 4); },
          "4 x 2, pixels: the black square's top-left, top-right, bottom-right, bottom-left "
          "corners of the upright tag")
      .def_property_readonly(
          "corner_covariance",
          [](const PyDetection& d) { return SquareMatrix(d.d.corner_covariance.val, 8); },
          "8 x 8, pixels squared: the covariance of the four corners as x0, y0, x1, y1, ...\n"
          "(the detector's estimate of how far they can be trusted)")
      .def_property_readonly(
          "center",
          [](const PyDetection& d) {
            const cv::Vec3d c = d.d.image_from_tag * cv::Vec3d(0.5, 0.5, 1);
            return py::make_tuple(c[0] / c[2], c[1] / c[2]);
          },
          "(x, y), pixels: the tag's centre through its homography")
      .def_property_readonly(
          "homography", [](const PyDetection& d) { return Matrix33(d.d.image_from_tag); },
          "image from tag: the unit square [0,1]^2 of the black square to pixels")
      .def_property_readonly(
          "pose",
          [](const PyDetection& d) -> py::object {
            if (!d.d.has_pose) return py::none();
            return py::cast(d.d.pose);
          },
          "a Pose when the Detector has a camera and tag size (or detect() was given them),\n"
          "else None")
      .def_property_readonly(
          "green_corners", [](const PyDetection& d) { return Points(d.d.green_corners.data(), 4); },
          "4 x 2, pixels: the green/black border's corners, in the order of corners")
      .def_property_readonly(
          "red_corners", [](const PyDetection& d) { return Points(d.d.red_corners.data(), 4); },
          "4 x 2, pixels: the red/green border's corners, in the order of corners");
}

}  // namespace

void BindDetections(py::module_& m) {
  BindPose(m);
  DetectionFields(m)
      .def("as_dict", &DetectionDict,
           "The detection as `chromatag detect --json` writes it: family, id, hamming, margin,\n"
           "corners, green_corners, red_corners (lists of [x, y]) and pose (rvec, tvec,\n"
           "rms_error_px, ambiguity) when there is one.")
      .def("__eq__",
           [](const PyDetection& a, const py::object& other) -> py::object {
             if (!py::isinstance<PyDetection>(other))
               return py::reinterpret_borrow<py::object>(Py_NotImplemented);
             return py::bool_(
                 DetectionState(a.d).equal(DetectionState(other.cast<const PyDetection&>().d)));
           })
      .def("__hash__",
           [](const PyDetection& d) {
             return py::hash(
                 py::make_tuple(d.d.family->name(), d.d.id, d.d.corners[0].x, d.d.corners[0].y));
           })
      .def(
          py::pickle([](const PyDetection& d) { return DetectionState(d.d); },
                     [](const py::tuple& state) { return PyDetection{DetectionFromState(state)}; }))
      .def("__repr__", [](const PyDetection& d) {
        char centre[64];
        const cv::Vec3d c = d.d.image_from_tag * cv::Vec3d(0.5, 0.5, 1);
        std::snprintf(centre, sizeof centre, "(%.1f, %.1f)", c[0] / c[2], c[1] / c[2]);
        return "Detection(family='" + d.d.family->name() + "', id=" + std::to_string(d.d.id) +
               ", hamming=" + std::to_string(d.d.hamming) + ", center=" + centre + ")";
      });
}

void BindDetector(py::module_& m) {
  py::class_<PyDetector>(
      m, "Detector",
      "Detector(families=('16h5', '36h11'), *, config=None, camera_matrix=None,\n"
      "         dist_coeffs=None, camera_model='pinhole', camera_file=None,\n"
      "         tag_size=0.0, **options)\n\n"
      "options are the names a detector config holds (step, row_step, adiff_thresh,\n"
      "border_thresh, min_decision_margin, white_balance, ...; docs/calibration.md) and\n"
      "report_rejected; config a file written by\n"
      "'chromatag calibrate'. The camera: camera_matrix and dist_coeffs as OpenCV's\n"
      "(camera_model 'fisheye' for cv::fisheye's k1-k4), or camera_file, an OpenCV,\n"
      "ROS or Kalibr file as 'chromatag calibrate-camera' writes. With a camera and\n"
      "tag_size (metres, side of the black square) each detection has a pose.")
      .def(py::init([](const py::object& families, const py::kwargs& kwargs) {
             return MakeDetector(families, kwargs);
           }),
           py::arg("families") = std::vector<std::string>{"16h5", "36h11"})
      .def("detect", &Detect, py::arg("image"), py::arg("order") = "bgr",
           py::arg("return_rejected") = false, py::arg("estimate_tag_pose") = false,
           py::arg("camera_params") = py::none(), py::arg("tag_size") = py::none(),
           "Detections in an H x W x 3 uint8 image (BGR as cv2.imread gives, or order='rgb').\n"
           "With return_rejected=True (and report_rejected=True in the options), also the\n"
           "candidates that were rejected, with their stage and reason. As pupil-apriltags:\n"
           "estimate_tag_pose=True with camera_params=(fx, fy, cx, cy) and tag_size (metres,\n"
           "the black square's side) gives each detection a pose for this call (no\n"
           "distortion; build the Detector with a camera for that).")
      .def("detect_board", &DetectBoard, py::arg("image"), py::arg("board"),
           py::arg("order") = "bgr",
           "(detections, pose): the detections in the image and the board's pose from all its\n"
           "tags among them (a BoardPose), or None when none of its tags is seen. Needs a\n"
           "Detector built with camera_matrix.")
      .def_property_readonly(
          "families", [](const PyDetector& d) { return d.detector->options().families; },
          "the families this detector looks for, e.g. ['16h5', '36h11']");

  m.def("draw_detections", &DrawOn, py::arg("image"), py::arg("detections"),
        py::arg("detector") = nullptr,
        "Draws the detections' outlines and IDs (and pose axes, given the detector that found\n"
        "them with a camera and tag size) on the image, in place; returns it.");
  m.def("draw_board_pose", &DrawBoardOn, py::arg("image"), py::arg("pose"), py::arg("detector"),
        py::arg("axis_length") = 0.1, py::arg("name") = "",
        "Draws a board's frame at its pose (x red, y green, z blue, axis_length metres) and\n"
        "its name on the image, in place, with the intrinsics of the detector that found it;\n"
        "returns it.");
}

}  // namespace chromatag::python
