// The checks: verify (a generated sheet) and verify_print (scans or photos
// of the printed one).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <optional>

#include "chromatag/base/units.h"
#include "chromatag/detector/config.h"
#include "chromatag/verify/print_check.h"
#include "chromatag/verify/sheet_check.h"
#include "common.h"

namespace chromatag::python {
namespace {

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

}  // namespace

void BindVerify(py::module_& m) {
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
}

}  // namespace chromatag::python
