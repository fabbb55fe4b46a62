// Boards and bundles: BoardTag, Board, BoardPose, Detector.detect_board and
// draw_board_pose.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>

#include "chromatag/detector/draw.h"
#include "chromatag/rig/board_file.h"
#include "common.h"

namespace chromatag::python {
namespace {

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

}  // namespace

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

namespace {

void BindBoardTag(py::module_& m) {
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
}

void BindBoard(py::module_& m) {
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
}

void BindBoardPose(py::module_& m) {
  py::class_<PyBoardPose>(m, "BoardPose", "A board's pose in the camera frame (metres)")
      .def_property_readonly(
          "rvec", [](const PyBoardPose& p) { return Vector(p.pose.rvec.val, 3); },
          "Rodrigues rotation of camera_from_board")
      .def_property_readonly(
          "tvec", [](const PyBoardPose& p) { return Vector(p.pose.tvec.val, 3); },
          "the board frame's origin in the camera frame")
      .def_property_readonly(
          "rotation", [](const PyBoardPose& p) { return RotationMatrix(p.pose.rvec); },
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
      .def_property_readonly(
          "covariance", [](const PyBoardPose& p) { return SquareMatrix(p.pose.covariance.val, 6); },
          "6 x 6 covariance in ROS's PoseWithCovariance order: x, y, z (metres), then a small\n"
          "rotation about the camera's x, y, z axes composed onto the pose (radians)")
      .def("__repr__", [](const PyBoardPose& p) {
        return "BoardPose(tvec=[" + std::to_string(p.pose.tvec[0]) + ", " +
               std::to_string(p.pose.tvec[1]) + ", " + std::to_string(p.pose.tvec[2]) +
               "], tags_used=" + std::to_string(p.tags_used.size()) + ")";
      });
}

}  // namespace

void BindBoards(py::module_& m) {
  BindBoardTag(m);
  BindBoard(m);
  BindBoardPose(m);
}

}  // namespace chromatag::python
