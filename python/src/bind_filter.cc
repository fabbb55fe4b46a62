// chromatag.PoseFilter and FilteredPose: a tag's or a board's pose followed
// over the frames of a video (detector/pose_filter.h).
#include <string>

#include "chromatag/detector/pose_filter.h"
#include "common.h"

namespace chromatag::python {
namespace {

PoseFilter MakeFilter(double translation_acceleration, double rotation_acceleration,
                      double gate_chi2, int frames_to_jump, double max_gap_s) {
  PoseFilterOptions options;
  options.translation_acceleration = translation_acceleration;
  options.rotation_acceleration = rotation_acceleration;
  options.gate_chi2 = gate_chi2;
  options.frames_to_jump = frames_to_jump;
  options.max_gap_s = max_gap_s;
  std::string error;
  if (!options.IsValid(&error)) throw Error(error);
  return PoseFilter(options);
}

// One frame's pose, a chromatag.Pose or a chromatag.BoardPose.
FilteredPose Update(PoseFilter& filter, double time_s, const py::object& pose) {
  if (py::isinstance<TagPose>(pose)) {
    const TagPose& p = pose.cast<const TagPose&>();
    return filter.Update(time_s, p.rvec, p.tvec, p.covariance);
  }
  if (py::isinstance<PyBoardPose>(pose)) {
    const BoardPose& p = pose.cast<const PyBoardPose&>().pose;
    return filter.Update(time_s, p.rvec, p.tvec, p.covariance);
  }
  throw Error("pose must be a chromatag.Pose or a chromatag.BoardPose, not " + Describe(pose));
}

}  // namespace

void BindFilter(py::module_& m) {
  py::class_<FilteredPose>(m, "FilteredPose", "PoseFilter.update's pose (metres)")
      .def_property_readonly(
          "rvec", [](const FilteredPose& p) { return Vector(p.rvec.val, 3); },
          "Rodrigues rotation, as Pose.rvec")
      .def_property_readonly(
          "tvec", [](const FilteredPose& p) { return Vector(p.tvec.val, 3); }, "as Pose.tvec")
      .def_property_readonly(
          "rotation", [](const FilteredPose& p) { return RotationMatrix(p.rvec); },
          "3 x 3 rotation matrix (rvec as a matrix)")
      .def_property_readonly(
          "covariance", [](const FilteredPose& p) { return SquareMatrix(p.covariance.val, 6); },
          "6 x 6 covariance in Pose.covariance's order and units (ROS's)")
      .def_readonly("used", &FilteredPose::used,
                    "whether the frame's pose was used; False when it lay too far from the "
                    "prediction and was left out (the pose is then the prediction)")
      .def_readonly("restarted", &FilteredPose::restarted,
                    "whether the filter (re)started at this frame: the first, after a gap, or a "
                    "jump (frames_to_jump frames in a row left out that agree)")
      .def("__repr__", [](const FilteredPose& p) {
        return "FilteredPose(tvec=[" + std::to_string(p.tvec[0]) + ", " +
               std::to_string(p.tvec[1]) + ", " + std::to_string(p.tvec[2]) +
               "], used=" + (p.used ? "True" : "False") + ")";
      });
  const PoseFilterOptions defaults;
  py::class_<PoseFilter>(
      m, "PoseFilter",
      "A tag's or a board's pose followed over the frames of a video: a Kalman filter on the\n"
      "pose and its velocity, each frame counting as much as its covariance says; a frame far\n"
      "from the prediction (the mirrored tilt) is left out, frames_to_jump of them in a row\n"
      "that agree are a move. One filter per tag or board.")
      .def(py::init(&MakeFilter), py::kw_only(),
           py::arg("translation_acceleration") = defaults.translation_acceleration,
           py::arg("rotation_acceleration") = defaults.rotation_acceleration,
           py::arg("gate_chi2") = defaults.gate_chi2,
           py::arg("frames_to_jump") = defaults.frames_to_jump,
           py::arg("max_gap_s") = defaults.max_gap_s,
           "How fast the motion may change (the velocity's change over a second, one standard\n"
           "deviation: m/s and rad/s a second; the defaults suit slow, smooth motion), the\n"
           "squared Mahalanobis distance beyond which a frame is left out, how many such frames\n"
           "in a row make a move, and the gap in seconds after which the filter starts again")
      .def("update", &Update, py::arg("time_s"), py::arg("pose"),
           "Feeds the pose (a Pose or a BoardPose) seen at time_s seconds (increasing; an\n"
           "earlier time starts the filter again) and returns the FilteredPose")
      .def("reset", &PoseFilter::Reset, "Forgets every frame")
      .def_property_readonly("started", &PoseFilter::started,
                             "whether a frame has been fed since the start or the last reset");
}

}  // namespace chromatag::python
