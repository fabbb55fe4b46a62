// What the Python module's files share: chromatag.Error, numpy arrays in
// and out, argument checks, the wrapped objects, and each area's Bind
// function (module.cc calls them in order).
#ifndef CHROMATAG_PYTHON_COMMON_H_
#define CHROMATAG_PYTHON_COMMON_H_

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detector.h"

namespace py = pybind11;

namespace chromatag::python {

// Raised as chromatag.Error (a ValueError) with the library's message.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// "bgr" or "rgb" (either case); Error for anything else.
PixelOrder OrderFrom(const std::string& order);

// A numpy image as a cv::Mat. 8-bit, H x W x 3 (or x 4, whose alpha is
// dropped); shares the array's memory when it is C-contiguous, copies it
// otherwise. *keep holds what the Mat points into.
cv::Mat ColourImage(const py::object& object, py::object* keep);

// A few numbers (a camera matrix, distortion coefficients, a position) as
// a C-order array of doubles, or an Error saying `expected`. The count is
// checked before the conversion: a broadcast view can describe billions of
// elements, and converting it would write every one out.
py::array_t<double, py::array::c_style | py::array::forcecast> SmallNumbers(
    const py::object& value, py::ssize_t max_count, const std::string& expected);

// n points as an n x 2 array, n numbers as a vector, a 3 x 3 matrix.
py::array_t<double> Points(const cv::Point2d* points, int n);
py::array_t<double> Vector(const double* values, int n);
py::array_t<double> Matrix33(const cv::Matx33d& m);
// A Rodrigues vector as its 3 x 3 rotation matrix.
py::array_t<double> RotationMatrix(const cv::Vec3d& rvec);
// An n x n row-major matrix as a numpy array.
py::array_t<double> SquareMatrix(const double* values, int n);

// What a value is, for messages: its type and a short repr.
std::string Describe(const py::handle& value);

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

// A path argument as the type stubs give it: None for none (""), a str or
// an os.PathLike (pathlib.Path) for a file.
std::string PathOrNone(const py::handle& value, const char* name);

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

// A board pose with the IDs of its tags (the Board may be gone).
struct PyBoardPose {
  BoardPose pose;
  std::vector<int> tags_used, tags_rejected;
};

// (detections, BoardPose or None): Detector.detect_board.
py::tuple DetectBoard(const PyDetector& self, const py::object& image, const Board& board,
                      const std::string& order);

// pickle's protocols 0 and 1 build an object through object.__new__ and
// copyreg, which a pybind11 class cannot take (the interpreter aborted: an
// instance without a registered base). A class with a state (py::pickle)
// is rebuilt at every protocol as protocol 2 does (copyreg.__newobj__, then
// __setstate__); any other refuses with TypeError, as protocol 2 did.
void PickleAtEveryProtocol(py::object cls);
void RefusePickling(py::object cls, const std::string& why);

// Each area's classes and functions, added to the module in this order (a
// signature names only the classes bound before it).
void BindDetections(py::module_& m);   // Pose, Detection (bind_detector.cc)
void BindBoards(py::module_& m);       // BoardTag, Board, BoardPose
void BindDetector(py::module_& m);     // Detector, draw_detections, draw_board_pose
void BindGenerator(py::module_& m);    // render_tag, generate, families, palettes
void BindVerify(py::module_& m);       // TagVerdict, SheetVerdict, verify, verify_print
void BindCalibration(py::module_& m);  // read_camera
void BindFilter(py::module_& m);       // PoseFilter, FilteredPose

}  // namespace chromatag::python

#endif  // CHROMATAG_PYTHON_COMMON_H_
