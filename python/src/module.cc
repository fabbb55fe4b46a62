// The Python module `chromatag` (pybind11, numpy arrays in and out):
// Detector, detect, draw_detections, render_tag, generate, verify, verify_print, and the
// families and palettes. docs/python.md shows it in use.
//
// Each area binds its own classes and functions (bind_detector.cc,
// bind_boards.cc, bind_generator.cc, bind_verify.cc, bind_calibration.cc);
// what they share is in common.h.
#include "chromatag/families/version.h"
#include "common.h"

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

  BindDetections(m);
  BindBoards(m);
  BindDetector(m);
  BindGenerator(m);
  BindVerify(m);
  BindCalibration(m);
  BindFilter(m);

  // What pickling does, said by every class at every protocol.
  for (const char* name : {"Detection", "BoardTag", "Board"}) PickleAtEveryProtocol(m.attr(name));
  RefusePickling(m.attr("Detector"),
                 "build a Detector in each process, from the same options or config file");
  for (const char* name : {"Pose", "BoardPose", "FilteredPose", "TagVerdict", "SheetVerdict"})
    RefusePickling(m.attr(name), "it is a result; keep the numbers it holds");
  RefusePickling(m.attr("PoseFilter"), "it follows one stream; start one in each process");
}
