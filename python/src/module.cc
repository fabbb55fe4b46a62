// The Python module `chromatag` (pybind11, numpy arrays in and out):
// Detector, detect, draw_detections, render_tag, generate, verify, verify_print, and the
// families and palettes. docs/python.md shows it in use.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <climits>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/calib/board_file.h"
#include "chromatag/calib/camera_file.h"
#include "chromatag/detector/board.h"
#include "chromatag/detector/config.h"
#include "chromatag/detector/detection_json.h"
#include "chromatag/detector/detector.h"
#include "chromatag/detector/draw.h"
#include "chromatag/detector/pose.h"
#include "chromatag/families/family.h"
#include "chromatag/families/input_file.h"
#include "chromatag/families/palette.h"
#include "chromatag/families/version.h"
#include "chromatag/generator/sheet.h"
#include "chromatag/generator/sheet_request.h"
#include "chromatag/generator/tag_renderer.h"
#include "chromatag/generator/units.h"
#include "chromatag/verify/print_check.h"
#include "chromatag/verify/sheet_check.h"

namespace py = pybind11;

namespace chromatag::python {
namespace {

// Raised as chromatag.Error (a ValueError) with the library's message.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

PixelOrder OrderFrom(const std::string& order) {
  if (order == "bgr" || order == "BGR") return PixelOrder::kBgr;
  if (order == "rgb" || order == "RGB") return PixelOrder::kRgb;
  throw Error("unknown pixel order '" + order +
              "' (allowed: \"bgr\", as OpenCV reads, or \"rgb\")");
}

// A numpy image as a cv::Mat. 8-bit, H x W x 3 (or x 4, whose alpha is
// dropped); shares the array's memory when it is C-contiguous, copies it
// otherwise. *keep holds what the Mat points into.
cv::Mat ColourImage(const py::object& object, py::object* keep) {
  // None is what cv2.imread gives for a file it could not read.
  if (object.is_none()) throw Error("the image is None (did cv2.imread fail to read the file?)");
  if (!py::isinstance<py::array>(object))
    throw Error("the image must be a numpy array (H x W x 3, uint8), not " +
                std::string(py::str(py::type::of(object).attr("__name__"))));
  const py::array image = py::reinterpret_borrow<py::array>(object);
  if (!py::isinstance<py::array_t<uint8_t>>(image) || image.dtype().kind() != 'u' ||
      image.itemsize() != 1) {
    throw Error("the image must be 8-bit (dtype uint8), not " +
                std::string(py::str(image.dtype())) +
                ": convert it, e.g. with cv2.convertScaleAbs");
  }
  if (image.ndim() == 2 || (image.ndim() == 3 && image.shape(2) == 1)) {
    throw Error(
        "ChromaTag needs a colour image (H x W x 3): its tags are told apart by colour, and this "
        "one is grey");
  }
  if (image.ndim() != 3 || (image.shape(2) != 3 && image.shape(2) != 4)) {
    throw Error("the image must be H x W x 3 (or x 4), not of shape " +
                std::string(py::str(py::tuple(py::cast(
                    std::vector<py::ssize_t>(image.shape(), image.shape() + image.ndim()))))));
  }
  // The budget before any copy (a broadcast view can claim gigabytes), and
  // sizes a cv::Mat can hold.
  const double pixels = static_cast<double>(image.shape(0)) * static_cast<double>(image.shape(1));
  if (pixels > static_cast<double>(kMaxImagePixels) || image.shape(0) > INT_MAX ||
      image.shape(1) > INT_MAX) {
    throw Error("the image is " + std::to_string(image.shape(1)) + " x " +
                std::to_string(image.shape(0)) + " pixels, over the limit of " +
                std::to_string(kMaxImagePixels >> 20) + " Mpx");
  }
  auto contiguous = py::array_t<uint8_t, py::array::c_style | py::array::forcecast>::ensure(image);
  if (!contiguous) throw py::error_already_set();  // numpy's own error, e.g. MemoryError.
  *keep = contiguous;
  const int rows = static_cast<int>(contiguous.shape(0));
  const int cols = static_cast<int>(contiguous.shape(1));
  const int channels = static_cast<int>(contiguous.shape(2));
  cv::Mat mat(rows, cols, CV_8UC(channels), const_cast<uint8_t*>(contiguous.data()));
  if (channels == 3) return mat;
  if (mat.empty()) return cv::Mat(rows, cols, CV_8UC3);  // Nothing to convert (0 rows or columns).
  cv::Mat three;
  cv::cvtColor(mat, three, cv::COLOR_BGRA2BGR);  // Drops the 4th channel whatever the order.
  return three;
}

// A few numbers (a camera matrix, distortion coefficients, a position) as
// a C-order array of doubles, or an Error saying `expected`. The count is
// checked before the conversion: a broadcast view can describe billions of
// elements, and converting it would write every one out.
py::array_t<double, py::array::c_style | py::array::forcecast> SmallNumbers(
    const py::object& value, py::ssize_t max_count, const std::string& expected) {
  const py::array array = py::array::ensure(value);  // No copy of an array.
  if (!array || array.size() > max_count) throw Error(expected);
  auto numbers = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!numbers) throw Error(expected);
  return numbers;
}

py::array_t<double> Points(const cv::Point2d* points, int n) {
  py::array_t<double> out({n, 2});
  auto view = out.mutable_unchecked<2>();
  for (int i = 0; i < n; ++i) {
    view(i, 0) = points[i].x;
    view(i, 1) = points[i].y;
  }
  return out;
}

py::array_t<double> Vector(const double* values, int n) {
  py::array_t<double> out(n);
  for (int i = 0; i < n; ++i) out.mutable_at(i) = values[i];
  return out;
}

py::array_t<double> Matrix33(const cv::Matx33d& m) {
  py::array_t<double> out({3, 3});
  auto view = out.mutable_unchecked<2>();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) view(r, c) = m(r, c);
  return out;
}

// The JSON value of a keyword argument, for ParseDetectorConfig.
// What a value is, for messages: its type and a short repr.
std::string Describe(const py::handle& value) {
  std::string repr = py::str(py::repr(value));
  if (repr.size() > 40) {
    size_t cut = 37;  // On a UTF-8 character boundary.
    while (cut > 0 && (static_cast<unsigned char>(repr[cut]) & 0xc0) == 0x80) --cut;
    repr = repr.substr(0, cut) + "...";
  }
  return std::string(py::str(value.get_type().attr("__name__"))) + " " + repr;
}

// `value` as T, or chromatag.Error naming the argument and what it must be
// (pybind11 would raise a bare RuntimeError, "Unable to cast Python instance").
template <typename T>
T Arg(const py::handle& value, const std::string& name, const std::string& what) {
  try {
    return value.cast<T>();
  } catch (const py::cast_error&) {
    throw Error(name + " must be " + what + ", not " + Describe(value));
  }
}

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

// A path argument as the type stubs give it: None for none (""), a str or
// an os.PathLike (pathlib.Path) for a file.
std::string PathOrNone(const py::handle& value, const char* name) {
  if (value.is_none()) return "";
  try {
    return value.cast<std::filesystem::path>().string();
  } catch (const py::cast_error&) {
    throw py::type_error(std::string(name) + " must be a path (str or os.PathLike) or None, not " +
                         py::type::of(value).attr("__name__").cast<std::string>());
  }
}

// How many tag-free frames of a Detector are also tried in the other
// channel order, to warn about an RGB frame passed as BGR (or the reverse):
// the check costs a second detection, so only a Detector's first 16 frames
// without a tag pay it.
constexpr int kOrderChecks = 16;

struct PyDetector {
  struct OrderCheck {
    std::atomic<int> left{kOrderChecks};
    std::atomic<bool> warned{false};  // Said once per Detector, across threads.
  };
  std::shared_ptr<const Detector> detector;
  std::shared_ptr<OrderCheck> order_check = std::make_shared<OrderCheck>();
};

// A detection that owns its copy (the family is process-wide, see TagFamily::Load).
struct PyDetection {
  Detection d;
};

PyDetector MakeDetector(const py::object& families, const py::kwargs& kwargs) {
  DetectorOptions options;
  options.families = {"16h5", "36h11"};
  nlohmann::json fields = nlohmann::json::object();
  if (py::isinstance<py::str>(families)) {
    fields["families"] = nlohmann::json::array({families.cast<std::string>()});
  } else {
    fields["families"] = JsonOf("families", families);
  }
  py::object camera_matrix = py::none(), dist_coeffs = py::none();
  double tag_size = 0.0;
  std::string config, camera_file, camera_model = "pinhole";
  bool model_given = false;
  for (const auto& item : kwargs) {
    const std::string name = item.first.cast<std::string>();
    if (name == "camera_matrix") {
      camera_matrix = py::reinterpret_borrow<py::object>(item.second);
    } else if (name == "dist_coeffs") {
      dist_coeffs = py::reinterpret_borrow<py::object>(item.second);
    } else if (name == "camera_model") {
      camera_model = py::str(item.second);
      model_given = true;
    } else if (name == "camera_file") {
      camera_file = PathOrNone(item.second, "camera_file");
    } else if (name == "tag_size") {
      tag_size = Arg<double>(item.second, "tag_size", "a number (metres)");
    } else if (name == "report_rejected") {
      options.report_rejected = Arg<bool>(item.second, "report_rejected", "True or False");
    } else if (name == "config") {
      config = PathOrNone(item.second, "config");
    } else {
      fields[name] = JsonOf(name, item.second);
    }
  }
  std::string error;
  const bool report_rejected = options.report_rejected;
  if (!config.empty() && !LoadDetectorConfig(config, &options, &error)) throw Error(error);
  options.report_rejected = report_rejected;
  const nlohmann::json text = {
      {"schema", kDetectorConfigSchema}, {"schema_version", 1}, {"options", fields}};
  if (!ParseDetectorConfig(text.dump(), &options, &error)) throw Error(error);
  if (!camera_matrix.is_none()) {
    const std::string k_expected =
        "camera_matrix must be 3 x 3 ([[fx, 0, cx], [0, fy, cy], [0, 0, 1]])";
    const auto k = SmallNumbers(camera_matrix, 9, k_expected);
    if (k.ndim() != 2 || k.shape(0) != 3 || k.shape(1) != 3) throw Error(k_expected);
    CameraIntrinsics camera;
    double matrix[9];
    for (int i = 0; i < 9; ++i) matrix[i] = k.at(i / 3, i % 3);
    if (!IntrinsicsFromMatrix(matrix, &camera, &error)) throw Error("camera_matrix: " + error);
    if (!dist_coeffs.is_none()) {
      const auto d = SmallNumbers(dist_coeffs, 64,
                                  "dist_coeffs must be numbers (k1, k2, p1, p2[, k3[, k4, k5, "
                                  "k6]])");
      for (py::ssize_t i = 0; i < d.size(); ++i) camera.distortion.push_back(d.data()[i]);
    }
    if (camera_model != "pinhole" && camera_model != "fisheye")
      throw Error("camera_model must be 'pinhole' or 'fisheye', not '" + camera_model + "'");
    camera.model = camera_model == "fisheye" ? LensModel::kFisheye : LensModel::kPinhole;
    if (!camera.IsValid(&error)) throw Error(error);
    options.camera = camera;
  } else if (!dist_coeffs.is_none()) {
    throw Error("dist_coeffs without camera_matrix");
  }
  if (!camera_file.empty()) {
    if (options.camera) throw Error("give camera_file or camera_matrix, not both");
    if (model_given) throw Error("camera_model comes from camera_file; give one or the other");
    CameraIntrinsics camera;
    if (!LoadCameraFile(camera_file, &camera, &error)) throw Error(error);
    options.camera = camera;
  }
  options.tag_size = tag_size;
  if (tag_size > 0 && !options.camera)
    throw Error("tag_size needs camera_matrix or camera_file for a pose");
  auto detector = Detector::Create(options, &error);
  if (!detector) throw Error(error);
  return {std::move(detector)};
}

py::object Detect(const PyDetector& self, const py::object& image, const std::string& order,
                  bool return_rejected, bool estimate_tag_pose, const py::object& camera_params,
                  const py::object& tag_size) {
  // pupil-apriltags' call shape: the camera and tag size for this call.
  CameraIntrinsics camera;
  double size = 0.0;
  if (estimate_tag_pose) {
    if (camera_params.is_none() || tag_size.is_none())
      throw Error("estimate_tag_pose needs camera_params=(fx, fy, cx, cy) and tag_size (metres)");
    const auto k = Arg<std::vector<double>>(camera_params, "camera_params", "(fx, fy, cx, cy)");
    if (k.size() != 4) throw Error("camera_params must be (fx, fy, cx, cy)");
    camera.fx = k[0];
    camera.fy = k[1];
    camera.cx = k[2];
    camera.cy = k[3];
    size = Arg<double>(tag_size, "tag_size", "a number (metres)");
    std::string error;
    if (!camera.IsValid(&error)) throw Error("camera_params: " + error);
    if (!(size > 0) || !std::isfinite(size))
      throw Error("tag_size must be a positive length, metres");
  } else if (!camera_params.is_none() || !tag_size.is_none()) {
    throw Error("camera_params and tag_size are for estimate_tag_pose=True");
  }
  py::object keep;
  const cv::Mat mat = ColourImage(image, &keep);
  const PixelOrder pixel_order = OrderFrom(order);
  DetectionResult result;
  size_t swapped_found = 0;
  {
    py::gil_scoped_release release;
    self.detector->Detect(mat, pixel_order, &result);
    if (estimate_tag_pose) {
      for (Detection& d : result.detections) d.has_pose = EstimateTagPose(d, camera, size, &d.pose);
    }
    PyDetector::OrderCheck& check = *self.order_check;
    if (result.detections.empty() && check.left.load() > 0 && check.left.fetch_sub(1) > 0) {
      const PixelOrder other =
          pixel_order == PixelOrder::kBgr ? PixelOrder::kRgb : PixelOrder::kBgr;
      swapped_found = self.detector->Detect(mat, other).detections.size();
      if (swapped_found > 0) {
        check.left = 0;
        if (check.warned.exchange(true)) swapped_found = 0;
      }
    }
  }
  if (swapped_found > 0) {
    const std::string given = pixel_order == PixelOrder::kBgr ? "bgr" : "rgb";
    const std::string other = pixel_order == PixelOrder::kBgr ? "rgb" : "bgr";
    const std::string message =
        "chromatag: no tag found with order='" + given + "', but " + std::to_string(swapped_found) +
        " with order='" + other + "': this image's red and blue look swapped (cv2.imread gives " +
        "BGR; PIL, imageio and most camera libraries give RGB). Pass order='" + other + "'.";
    if (PyErr_WarnEx(PyExc_UserWarning, message.c_str(), 1) != 0) throw py::error_already_set();
  }
  py::list detections;
  for (Detection& d : result.detections) detections.append(PyDetection{std::move(d)});
  if (!return_rejected) return std::move(detections);
  py::list rejected;
  for (const RejectedCandidate& r : result.rejected) {
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
    rejected.append(entry);
  }
  return py::make_tuple(detections, rejected);
}

// A board pose with the IDs of its tags (the Board may be gone).
struct PyBoardPose {
  BoardPose pose;
  std::vector<int> tags_used, tags_rejected;
};

Board MakeBoard(const std::string& name, const py::iterable& tags) {
  Board board;
  board.name = name;
  for (const py::handle& item : tags)
    board.tags.push_back(Arg<BoardTag>(item, "a Board's tags", "BoardTag objects"));
  std::string error;
  if (!board.IsValid(&error)) throw Error(error);
  return board;
}

BoardTag MakeBoardTag(const std::string& family, int id, double size, const py::object& position,
                      const py::object& rotation) {
  BoardTag tag;
  tag.family = family.rfind("tag", 0) == 0 ? family.substr(3) : family;
  tag.id = id;
  tag.size = size;
  const std::string t_expected = "position must be 3 numbers (x, y, z), metres";
  const auto t = SmallNumbers(position, 3, t_expected);
  if (t.size() != 3) throw Error(t_expected);
  tag.translation = {t.data()[0], t.data()[1], t.data()[2]};
  if (!rotation.is_none()) {
    const std::string r_expected = "rotation must be 3 x 3 (body_from_tag)";
    const auto r = SmallNumbers(rotation, 9, r_expected);
    if (r.ndim() != 2 || r.shape(0) != 3 || r.shape(1) != 3) throw Error(r_expected);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) tag.rotation(i, j) = r.at(i, j);
  }
  return tag;
}

py::tuple DetectBoard(const PyDetector& self, const py::object& image, const Board& board,
                      const std::string& order) {
  const DetectorOptions& options = self.detector->options();
  if (!options.camera)
    throw Error("detect_board needs a Detector built with camera_matrix (and dist_coeffs)");
  py::object keep;
  const cv::Mat mat = ColourImage(image, &keep);
  const PixelOrder pixel_order = OrderFrom(order);
  DetectionResult result;
  PyBoardPose pose;
  bool seen = false;
  {
    py::gil_scoped_release release;
    self.detector->Detect(mat, pixel_order, &result);
    seen = EstimateBoardPose(result.detections, board, *options.camera, &pose.pose);
  }
  if (seen) {
    for (int i : pose.pose.tags_used) pose.tags_used.push_back(board.tags[i].id);
    for (int i : pose.pose.detections_rejected)
      pose.tags_rejected.push_back(result.detections[i].id);
  }
  py::list detections;
  for (Detection& d : result.detections) detections.append(PyDetection{std::move(d)});
  if (!seen) return py::make_tuple(detections, py::none());
  return py::make_tuple(detections, pose);
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

py::array RenderTag(const std::string& family_name, int id, double cell_px,
                    const std::string& palette_name, int quiet_zone, const std::string& order) {
  std::string error;
  const auto family = TagFamily::Load(family_name, &error);
  if (!family) throw Error(error);
  if (!family->IsValidId(id, &error)) throw Error(error);
  const auto palette = BuiltinPalette(palette_name, &error);
  if (!palette) throw Error(error);
  if (!(cell_px >= 1.0 && cell_px <= 1000.0))
    throw Error("cell_px must lie in [1, 1000] pixels per cell");
  if (quiet_zone < 1 || quiet_zone > 20) throw Error("quiet_zone must lie in [1, 20] cells");
  const PixelOrder pixel_order = OrderFrom(order);
  TagDrawOptions draw;
  draw.quiet_zone_cells = quiet_zone;
  const RgbImage rgb = RasterizeTag(*family, id, TagColors::FromPalette(*palette), cell_px, draw);
  py::array_t<uint8_t> out({rgb.height, rgb.width, 3});
  auto view = out.mutable_unchecked<3>();
  for (int y = 0; y < rgb.height; ++y) {
    for (int x = 0; x < rgb.width; ++x) {
      const uint8_t* p = rgb.At(x, y);
      for (int c = 0; c < 3; ++c) view(y, x, c) = p[pixel_order == PixelOrder::kRgb ? c : 2 - c];
    }
  }
  return out;
}

std::vector<std::string> Generate(
    const std::filesystem::path& output_path, const std::string& family, const py::object& ids,
    const std::string& size, const std::string& page, const std::string& margin,
    const std::string& gap, int quiet_zone, const std::string& palette,
    const std::filesystem::path& palette_file_path, const std::filesystem::path& color_lut_path,
    const std::string& format, double dpi, bool label, bool crop_marks, bool cut_ring,
    bool one_per_page, const std::string& board, const std::string& spacing) {
  const std::string output = output_path.string(), palette_file = palette_file_path.string(),
                    color_lut = color_lut_path.string();
  SheetRequest request;
  request.family = family;
  request.board = board;
  request.spacing = spacing;
  if (ids.is_none()) {
    request.all = board.empty();  // A board takes the family's first kept IDs.
  } else if (py::isinstance<py::str>(ids)) {
    request.ids = ids.cast<std::string>();
  } else if (py::isinstance<py::int_>(ids)) {
    request.ids = std::to_string(Arg<int>(ids, "ids", "tag IDs (small integers)"));
  } else {
    for (const py::handle& id : ids)
      request.ids += (request.ids.empty() ? "" : ",") +
                     std::to_string(Arg<int>(id, "ids", "tag IDs (small integers)"));
    if (request.ids.empty()) throw Error("ids is empty: give some IDs, or None for every kept ID");
  }
  request.size = size;
  request.page = page;
  request.margin = margin;
  request.gap = gap;
  request.quiet_zone = quiet_zone;
  request.palette = palette;
  request.palette_file = palette_file;
  request.color_lut = color_lut;
  request.format = format;
  request.dpi = dpi;
  request.label = label;
  request.crop_marks = crop_marks;
  request.cut_ring = cut_ring;
  request.one_per_page = one_per_page;
  SheetOptions options;
  std::string error;
  if (!ToSheetOptions(request, output, &options, &error)) throw Error(error);
  std::vector<std::string> written;
  bool ok = false;
  {
    py::gil_scoped_release release;
    ok = WriteSheet(options, output, &error, &written);
  }
  if (!ok) throw Error(error);
  return written;
}

SheetVerdict Verify(const std::filesystem::path& sheet_path, double dpi,
                    const std::string& tolerance) {
  const std::string sheet = sheet_path.string();
  VerifyOptions options;
  options.dpi = dpi;
  std::string error;
  const auto length = ParseLength(tolerance, &error);
  if (!length) throw Error(error);
  options.max_position_error_mm = length->mm;
  std::optional<SheetVerdict> verdict;
  {
    py::gil_scoped_release release;
    verdict = VerifySheetFile(sheet, options, &error);
  }
  if (!verdict) throw Error(error);
  return *verdict;
}

// verify --print: the verdict as the CLI's JSON, parsed into Python objects.
py::object VerifyPrint(const std::filesystem::path& sheet_path,
                       const std::vector<std::filesystem::path>& image_paths, bool scans,
                       double scan_dpi, double scale_tolerance,
                       const std::optional<std::filesystem::path>& config_path) {
  const std::string sheet = sheet_path.string();
  std::vector<std::string> images;
  for (const auto& image : image_paths) images.push_back(image.string());
  const std::optional<std::string> config =
      config_path ? std::optional<std::string>(config_path->string()) : std::nullopt;
  std::string error;
  const auto record = ReadPrintedSheet(sheet, &error);
  if (!record) throw Error(error);
  PrintCheckOptions options;
  options.scans = scans || scan_dpi > 0;
  options.scan_dpi = scan_dpi;
  options.max_scale_error = scale_tolerance;
  if (config && !LoadDetectorConfig(*config, &options.detector, &error)) throw Error(error);
  std::string json;
  {
    py::gil_scoped_release release;
    const auto verdict = CheckPrintFiles(*record, images, options, &error);
    if (verdict) json = PrintVerdictJson(*record, *verdict);
  }
  if (json.empty()) throw Error(error);
  return py::module_::import("json").attr("loads")(json);
}

py::dict FamilyInfo(const std::string& name) {
  std::string error;
  const auto family = TagFamily::Load(name, &error);
  if (!family) throw Error(error);
  py::dict out;
  out["name"] = family->name();
  out["payload_width"] = family->payload_width();
  out["black_square_cells"] = family->black_square_cells();
  out["min_hamming"] = family->min_hamming();
  out["kept_ids"] = family->kept_ids();
  return out;
}

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

py::dict PaletteInfo(const std::string& name) {
  std::string error;
  const auto palette = BuiltinPalette(name, &error);
  if (!palette) throw Error(error);
  py::dict shades;
  for (Shade shade : kAllShades) {
    const Lab& lab = (*palette)[shade];
    const Rgb8 rgb = palette->Srgb8(shade);
    py::dict entry;
    entry["lab"] = py::make_tuple(lab.L, lab.a, lab.b);
    entry["srgb"] = py::make_tuple(rgb.r, rgb.g, rgb.b);
    shades[ShadeName(shade)] = entry;
  }
  py::dict out;
  out["name"] = palette->name;
  out["description"] = palette->description;
  out["shades"] = shades;
  return out;
}

// A Detection as `chromatag detect --json` writes it: the detector's one
// JSON writer, parsed into Python objects.
py::object DetectionDict(const PyDetection& detection) {
  return py::module_::import("json").attr("loads")(DetectionJson(detection.d));
}

// Every field of a Detection, for pickling: the family by name.
py::tuple DetectionState(const Detection& d) {
  std::vector<double> numbers;
  for (const auto* ring : {&d.corners, &d.green_corners, &d.red_corners})
    for (const cv::Point2d& p : *ring) numbers.insert(numbers.end(), {p.x, p.y});
  for (int i = 0; i < 9; ++i) numbers.push_back(d.image_from_tag.val[i]);
  for (int i = 0; i < 3; ++i) numbers.insert(numbers.end(), {d.pose.rvec[i], d.pose.tvec[i]});
  numbers.insert(numbers.end(), {d.pose.rms_error_px, d.pose.ambiguity, d.decision_margin});
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
      numbers.size() != 24 + 9 + 6 + 3 ||
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
  return d;
}

// A BoardTag's fields, for pickling.
py::tuple BoardTagState(const BoardTag& t) {
  return py::make_tuple(t.family, t.id, t.size,
                        std::vector<double>(t.translation.val, t.translation.val + 3),
                        std::vector<double>(t.rotation.val, t.rotation.val + 9));
}

BoardTag BoardTagFromState(const py::tuple& state) {
  const char* bad = "not a pickled chromatag.BoardTag";
  if (state.size() != 5) throw Error(bad);
  BoardTag t;
  std::vector<double> position, rotation;
  try {
    t.family = state[0].cast<std::string>();
    t.id = state[1].cast<int>();
    t.size = state[2].cast<double>();
    position = state[3].cast<std::vector<double>>();
    rotation = state[4].cast<std::vector<double>>();
  } catch (const py::cast_error&) {
    throw Error(bad);
  }
  if (position.size() != 3 || rotation.size() != 9) throw Error(bad);
  std::copy(position.begin(), position.end(), t.translation.val);
  std::copy(rotation.begin(), rotation.end(), t.rotation.val);
  return t;
}

// A Board's fields, for pickling; restored through the same checks as
// Board(name, tags).
py::tuple BoardState(const Board& b) {
  py::list tags;
  for (const BoardTag& t : b.tags) tags.append(BoardTagState(t));
  return py::make_tuple(b.name, b.palette, tags);
}

Board BoardFromState(const py::tuple& state) {
  const char* bad = "not a pickled chromatag.Board";
  if (state.size() != 3) throw Error(bad);
  Board b;
  try {
    b.name = state[0].cast<std::string>();
    b.palette = state[1].cast<std::string>();
    for (const py::handle& tag : state[2].cast<py::list>())
      b.tags.push_back(BoardTagFromState(tag.cast<py::tuple>()));
  } catch (const py::cast_error&) {
    throw Error(bad);
  }
  std::string error;
  if (!b.IsValid(&error)) throw Error(std::string(bad) + " (" + error + ")");
  return b;
}

// pickle's protocols 0 and 1 build an object through object.__new__ and
// copyreg, which a pybind11 class cannot take (the interpreter aborted: an
// instance without a registered base). A class with a state (py::pickle)
// is rebuilt at every protocol as protocol 2 does (copyreg.__newobj__, then
// __setstate__); any other refuses with TypeError, as protocol 2 did.
void PickleAtEveryProtocol(py::object cls) {
  auto reduce = [](const py::object& self) {
    return py::make_tuple(py::module_::import("copyreg").attr("__newobj__"),
                          py::make_tuple(py::type::of(self)), self.attr("__getstate__")());
  };
  py::setattr(cls, "__reduce_ex__",
              py::cpp_function([reduce](const py::object& self, int) { return reduce(self); },
                               py::is_method(cls)));
  py::setattr(cls, "__reduce__", py::cpp_function(reduce, py::is_method(cls)));
}

void RefusePickling(py::object cls, const std::string& why) {
  auto refuse = [why](const py::object& self) -> py::object {
    throw py::type_error("cannot pickle '" +
                         py::type::of(self).attr("__qualname__").cast<std::string>() +
                         "' object: " + why);
  };
  py::setattr(cls, "__reduce_ex__",
              py::cpp_function([refuse](const py::object& self, int) { return refuse(self); },
                               py::is_method(cls)));
  py::setattr(cls, "__reduce__", py::cpp_function(refuse, py::is_method(cls)));
}

}  // namespace
}  // namespace chromatag::python

PYBIND11_MODULE(_chromatag, m) {
  using namespace chromatag;
  using namespace chromatag::python;
  m.doc() = "ChromaTag coloured fiducial markers: detect, draw, render, generate and verify";
  m.attr("__version__") = kVersion;
  static py::exception<Error> error(m, "Error", PyExc_ValueError);
  error.attr("__doc__") =
      "A bad argument, an unreadable or broken file, or a request that cannot be met; the\n"
      "message says what was wrong and what is allowed. A subclass of ValueError.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  py::class_<TagPose>(m, "Pose", "A tag's pose in the camera frame (metres)")
      .def_property_readonly(
          "rvec", [](const TagPose& p) { return Vector(p.rvec.val, 3); },
          "Rodrigues rotation of camera_from_tag")
      .def_property_readonly(
          "tvec", [](const TagPose& p) { return Vector(p.tvec.val, 3); },
          "the tag's centre in the camera frame")
      .def_property_readonly(
          "rotation",
          [](const TagPose& p) {
            cv::Matx33d r;
            cv::Rodrigues(p.rvec, r);
            return Matrix33(r);
          },
          "3 x 3 rotation matrix of camera_from_tag (rvec as a matrix); the tag frame: x\n"
          "right, y up, z out of the tag, origin at its centre")
      .def_readonly("rms_error_px", &TagPose::rms_error_px,
                    "root mean square reprojection error over the twelve ring corners, pixels")
      .def_readonly("ambiguity", &TagPose::ambiguity,
                    "the kept planar solution's error over the other's: near 0 settled, near 1 "
                    "ambiguous (the tilt may be mirrored)")
      .def("__repr__", [](const TagPose& p) {
        return "Pose(tvec=[" + std::to_string(p.tvec[0]) + ", " + std::to_string(p.tvec[1]) + ", " +
               std::to_string(p.tvec[2]) + "])";
      });

  py::class_<PyDetection>(
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
          "4 x 2, pixels: the red/green border's corners, in the order of corners")
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

  py::class_<BoardTag>(m, "BoardTag",
                       "BoardTag(family, id, size, position, rotation=None)\n\n"
                       "One tag of a board: the side of its black square (metres), its centre\n"
                       "in the board frame and its rotation body_from_tag (3 x 3; None: the\n"
                       "board's axes). The tag frame: x right, y up, z out of the tag.")
      .def(py::init(&MakeBoardTag), py::arg("family"), py::arg("id"), py::arg("size"),
           py::arg("position"), py::arg("rotation") = py::none())
      .def_readonly("family", &BoardTag::family, "the tag's family: '16h5' or '36h11'")
      .def_readonly("id", &BoardTag::id, "the tag's ID in its family")
      .def_readonly("size", &BoardTag::size, "side of the black square, metres")
      .def_property_readonly(
          "position", [](const BoardTag& t) { return Vector(t.translation.val, 3); },
          "the tag's centre in the board frame, metres")
      .def_property_readonly(
          "rotation", [](const BoardTag& t) { return Matrix33(t.rotation); }, "body_from_tag")
      .def(py::pickle([](const BoardTag& t) { return BoardTagState(t); },
                      [](const py::tuple& state) { return BoardTagFromState(state); }))
      .def("__repr__", [](const BoardTag& t) {
        return "BoardTag(family='" + t.family + "', id=" + std::to_string(t.id) +
               ", size=" + std::to_string(t.size) + ")";
      });

  py::class_<Board>(m, "Board",
                    "Board(name, tags): tags fixed to one body (a printed board, a bundle).\n"
                    "Board.from_file reads a sheet's sidecar or a bundle YAML (docs/pose.md).")
      .def(py::init(&MakeBoard), py::arg("name"), py::arg("tags"))
      .def_static(
          "from_file",
          [](const std::filesystem::path& path) {
            std::string error;
            auto board = ReadBoardFile(path.string(), &error);
            if (!board) throw Error(error);
            return *board;
          },
          py::arg("path"),
          "A board file: a sheet from generate --board or calib-sheet (.pdf, .svg, .png, its\n"
          "sidecar beside it), its sidecar (.json), or a bundle YAML (.yaml, apriltag_ros's\n"
          "tag_bundles shape; 'file.yaml#name' picks a bundle).")
      .def_readonly("name", &Board::name, "the board's name (its file's, or the bundle's)")
      .def_readonly("palette", &Board::palette,
                    "the palette its sheet was printed with, when its file records one")
      .def_readonly("tags", &Board::tags, "its tags, a list of BoardTag")
      .def("__len__", [](const Board& b) { return b.tags.size(); })
      .def(py::pickle([](const Board& b) { return BoardState(b); },
                      [](const py::tuple& state) { return BoardFromState(state); }))
      .def("__repr__", [](const Board& b) {
        return "Board(name='" + b.name + "', tags=" + std::to_string(b.tags.size()) + ")";
      });

  py::class_<PyBoardPose>(m, "BoardPose", "A board's pose in the camera frame (metres)")
      .def_property_readonly(
          "rvec", [](const PyBoardPose& p) { return Vector(p.pose.rvec.val, 3); },
          "Rodrigues rotation of camera_from_board")
      .def_property_readonly(
          "tvec", [](const PyBoardPose& p) { return Vector(p.pose.tvec.val, 3); },
          "the board frame's origin in the camera frame")
      .def_property_readonly(
          "rotation",
          [](const PyBoardPose& p) {
            cv::Matx33d r;
            cv::Rodrigues(p.pose.rvec, r);
            return Matrix33(r);
          },
          "3 x 3 rotation matrix of camera_from_board (rvec as a matrix)")
      .def_readonly("tags_used", &PyBoardPose::tags_used, "IDs of the tags the pose fits")
      .def_readonly("tags_rejected", &PyBoardPose::tags_rejected,
                    "IDs of the detections left out: seen where the other tags say they are not "
                    "(a misread ID, a misplaced tag, a second copy)")
      .def_property_readonly(
          "rms_error_px", [](const PyBoardPose& p) { return p.pose.rms_error_px; },
          "root mean square reprojection error over the used tags' ring corners, pixels")
      .def_property_readonly(
          "ambiguity", [](const PyBoardPose& p) { return p.pose.ambiguity; },
          "the pose's error over the best other solution's: near 0 settled, near 1 ambiguous")
      .def("__repr__", [](const PyBoardPose& p) {
        return "BoardPose(tvec=[" + std::to_string(p.pose.tvec[0]) + ", " +
               std::to_string(p.pose.tvec[1]) + ", " + std::to_string(p.pose.tvec[2]) +
               "], tags_used=" + std::to_string(p.tags_used.size()) + ")";
      });

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
  m.def("render_tag", &RenderTag, py::arg("family"), py::arg("id"), py::arg("cell_px") = 10.0,
        py::arg("palette") = "default", py::arg("quiet_zone") = 2, py::arg("order") = "bgr",
        "One tag with its quiet zone as an H x W x 3 uint8 image, cell_px pixels per cell.");
  m.def("generate", &Generate, py::arg("output"), py::kw_only(), py::arg("family") = "16h5",
        py::arg("ids") = py::none(), py::arg("size") = "", py::arg("page") = "a4",
        py::arg("margin") = "10mm", py::arg("gap") = "5mm", py::arg("quiet_zone") = 2,
        py::arg("palette") = "default", py::arg("palette_file") = "", py::arg("color_lut") = "",
        py::arg("format") = "", py::arg("dpi") = 300.0, py::arg("label") = true,
        py::arg("crop_marks") = false, py::arg("cut_ring") = false, py::arg("one_per_page") = false,
        py::arg("board") = "", py::arg("spacing") = "",
        "Writes a print-ready sheet (PDF, SVG or PNG, from the extension) and its sidecar\n"
        "(output + '.json'), as 'chromatag generate' does; ids: a list, '0-9,12', or None for\n"
        "every kept ID (a board: its first COLS * ROWS). size: default 40mm, or for a board\n"
        "the largest that fits. board: 'COLSxROWS' lays the tags out as a board whose sidecar\n"
        "is its board file (Board.from_file). Returns the paths written.");

  py::class_<TagVerdict>(
      m, "TagVerdict",
      "verify()'s verdict on one tag of the sheet's sidecar: was it found once,\n"
      "with its ID, where the sidecar places it")
      .def_property_readonly(
          "id", [](const TagVerdict& v) { return v.expected.id; }, "the ID the sidecar expects")
      .def_property_readonly(
          "page", [](const TagVerdict& v) { return v.expected.page; }, "the page it is on, from 0")
      .def_readonly("found_id", &TagVerdict::found_id,
                    "the ID detected at its place (the first, if several); -1 if none")
      .def_readonly("times_found", &TagVerdict::times_found,
                    "how many detections fall at its place (1 when it passes)")
      .def_readonly("hamming", &TagVerdict::hamming, "bits corrected when it was decoded")
      .def_readonly("margin", &TagVerdict::margin, "the detection's decision margin")
      .def_readonly("position_error_mm", &TagVerdict::position_error_mm,
                    "the worst corner's distance from where the sidecar puts it, mm")
      .def_readonly("passed", &TagVerdict::passed, "whether this tag passes")
      .def_readonly("problem", &TagVerdict::problem,
                    "empty when it passes; otherwise what is wrong");
  py::class_<SheetVerdict>(m, "SheetVerdict",
                           "verify()'s verdict on a sheet: every tag of its sidecar, detections\n"
                           "where it has none, and problems with the files themselves")
      .def_readonly("passed", &SheetVerdict::passed,
                    "whether every tag passes, nothing unexpected is found and the files match")
      .def_readonly("tags_passed", &SheetVerdict::tags_passed, "how many tags pass")
      .def_readonly("tags", &SheetVerdict::tags, "a TagVerdict per tag of the sidecar")
      .def_readonly("file_problems", &SheetVerdict::file_problems,
                    "files changed since they were generated (their SHA-256 differs)")
      .def_property_readonly(
          "unexpected",
          [](const SheetVerdict& v) {
            py::list out;
            for (const auto& u : v.unexpected)
              out.append(py::make_tuple(u.page, u.family, u.id, u.center_mm[0], u.center_mm[1]));
            return out;
          },
          "detections where the sidecar has no tag: (page, family, id, x_mm, y_mm) tuples");
  m.def("verify", &Verify, py::arg("sheet"), py::kw_only(), py::arg("dpi") = 200.0,
        py::arg("tolerance") = "0.5mm",
        "Rasterises a generated sheet, detects every tag and checks it against the sidecar, as\n"
        "'chromatag verify' does.");

  m.def("verify_print", &VerifyPrint, py::arg("sheet"), py::arg("images"), py::kw_only(),
        py::arg("scans") = false, py::arg("scan_dpi") = 0.0, py::arg("scale_tolerance") = 0.005,
        py::arg("config") = py::none(),
        "Checks scans (scans=True; resolution from the files or scan_dpi) or photos of the\n"
        "printed sheet, as 'chromatag verify SHEET --print IMAGES' does; returns its JSON\n"
        "verdict as a dict (docs/verify.md, 'Check your print').");
  m.def("families", &TagFamily::Names, "The families: ['16h5', '36h11']");
  m.def("family", &FamilyInfo, py::arg("name"), "A family's geometry, distance and kept IDs");
  m.def("read_camera", &ReadCamera, py::arg("path"),
        "A camera file's intrinsics (OpenCV, ROS camera_info or Kalibr YAML; OpenCV JSON or XML),\n"
        "as the CLI's --camera reads them: {'camera_matrix': 3x3, 'dist_coeffs', 'camera_model':\n"
        "'pinhole' or 'fisheye', 'image_size': (w, h) or None}.\n"
        "Detector(camera_file=path) takes the same file.");
  m.def("palettes", &BuiltinPaletteNames, "The built-in palettes");
  m.def("palette", &PaletteInfo, py::arg("name"), "A palette's six shades in CIELAB and sRGB");

  // What pickling does, said by every class at every protocol.
  for (const char* name : {"Detection", "BoardTag", "Board"}) PickleAtEveryProtocol(m.attr(name));
  RefusePickling(m.attr("Detector"),
                 "build a Detector in each process, from the same options or config file");
  for (const char* name : {"Pose", "BoardPose", "TagVerdict", "SheetVerdict"})
    RefusePickling(m.attr(name), "it is a result; keep the numbers it holds");
}
