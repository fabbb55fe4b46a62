#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <set>

#include "chromatag/base/output_files.h"
#include "chromatag/base/units.h"
#include "chromatag/detector/config.h"
#include "chromatag/families/palette.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/rig/camera_file.h"
#include "chromatag/verify/family_check.h"
#include "chromatag/verify/print_check.h"
#include "chromatag/verify/sheet_check.h"
#include "chromatag/verify/stress.h"
#include "commands.h"
#include "flag_terms.h"
#include "progress.h"

namespace chromatag::cli {
namespace {

struct VerifyCommandOptions {
  std::string sheet;
  std::string family;
  bool all = false;
  bool stress = false;
  double dpi = 200.0;
  std::string tolerance = "0.5mm";
  std::string palette = "default";
  std::string palette_file;
  bool json = false;
  // --print: scans or photos of the printed sheet.
  std::vector<std::string> prints;
  bool scan = false;
  double scan_dpi = 0.0;
  std::string scale_tolerance = "0.5%";
  std::string config;
  std::string camera_file;
  std::string report;
};

void PrintSheet(const SheetVerdict& verdict) {
  Print("  %5s %4s %5s %7s %7s %9s  %s\n", "ID", "page", "found", "hamming", "margin", "error mm",
        "verdict");
  for (const auto& t : verdict.tags) {
    Print("  %5d %4d %5d %7d %7.1f %9.2f  %s\n", t.expected.id, t.expected.page + 1, t.times_found,
          t.hamming, t.margin, t.position_error_mm, t.passed ? "ok" : t.problem.c_str());
  }
  for (const auto& u : verdict.unexpected) {
    Print("  unexpected: %s ID %d on page %d at %.1f, %.1f mm, where the sidecar has no tag\n",
          u.family.c_str(), u.id, u.page + 1, u.center_mm[0], u.center_mm[1]);
  }
  for (const auto& problem : verdict.file_problems) Print("  file: %s\n", problem.c_str());
  Print("%d of %zu %s%s. %s\n", verdict.tags_passed, verdict.tags.size(),
        verdict.tags.size() == 1 ? "tag passes" : "tags pass",
        verdict.unexpected.empty() ? ", nothing else found" : "", verdict.passed ? "PASS" : "FAIL");
}

void PrintAudit(const std::string& family, const FamilyAudit& audit) {
  Print("\nFamily audit, %s: %d codes, minimum distance %d over rotations, radius %d\n",
        family.c_str(), audit.num_codes, audit.min_distance, audit.radius);
  Print("  pairs by distance:");
  for (size_t d = 0; d < audit.histogram.size(); ++d) {
    if (audit.histogram[d] > 0) Print(" %zu:%lld", d, static_cast<long long>(audit.histogram[d]));
  }
  Print("\n  closest pairs (ID a, ID b turned k quarter turns, distance):");
  for (size_t i = 0; i < std::min<size_t>(audit.closest_pairs.size(), 10); ++i) {
    const auto& p = audit.closest_pairs[i];
    Print("%s %d-%d/%d:%d", i ? "," : "", p.id_a, p.id_b, p.rotation, p.distance);
  }
  Print("\n  bit flips   trials      correct   wrong ID    rejected\n");
  for (const auto& f : audit.flips) {
    Print("  %9d %8lld%s %11lld %10lld %11lld\n", f.flips, static_cast<long long>(f.trials),
          f.exhaustive ? "*" : " ", static_cast<long long>(f.correct),
          static_cast<long long>(f.wrong_id), static_cast<long long>(f.rejected));
  }
  Print("  (* every pattern; otherwise a random sample)  decoding within the radius: %s\n",
        audit.DecodingIsSafe() ? "always right" : "NOT SAFE");
}

void PrintStress(const std::vector<TagStress>& stresses) {
  if (stresses.empty()) return;
  Print("\nStress (face-on sizes and tilts are the black square's side in pixels):\n");
  Print("  %5s %9s %9s", "ID", "min size", "max tilt");
  for (const auto& c : stresses[0].conditions) Print(" %14s", c.condition.c_str());
  Print("\n");
  for (const auto& s : stresses) {
    Print("  %5d %9.1f %9.0f", s.id, s.smallest_size_px, s.largest_tilt_deg);
    for (const auto& c : s.conditions) Print(" %14s", c.decoded ? "ok" : "FAIL");
    Print("\n");
  }
  std::vector<TagStress> weakest = stresses;
  std::sort(weakest.begin(), weakest.end(), [](const TagStress& a, const TagStress& b) {
    auto fails = [](const TagStress& s) {
      return std::count_if(s.conditions.begin(), s.conditions.end(),
                           [](const ConditionOutcome& c) { return !c.decoded; });
    };
    return std::make_tuple(-fails(a), -a.smallest_size_px, a.largest_tilt_deg) <
           std::make_tuple(-fails(b), -b.smallest_size_px, b.largest_tilt_deg);
  });
  Print("  weakest IDs:");
  for (size_t i = 0; i < std::min<size_t>(5, weakest.size()); ++i) Print(" %d", weakest[i].id);
  Print("\n");
}

std::vector<TagStress> RunStress(const TagFamily& family, const std::vector<int>& ids,
                                 const Palette& palette) {
  DetectorOptions options;
  options.families = {family.name()};
  auto detector = Detector::Create(options);
  const TagColors colors = TagColors::FromPalette(palette);
  std::vector<TagStress> stresses;
  Progress progress("stress", "tags", ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    stresses.push_back(StressTag(family, ids[i], colors, *detector));
    progress.Update(i + 1);
  }
  return stresses;
}

// The last line: how many tags pass, which pages' shape was not checked, the grade.
void PrintPrintSummary(const PrintVerdict& verdict) {
  // A page's shape counts as checked when any image of it measured it.
  std::set<int> shape_checked, shape_unchecked;
  for (const PrintPageResult& r : verdict.images) {
    if (r.page >= 0) (r.geometry_checked ? shape_checked : shape_unchecked).insert(r.page);
  }
  int unchecked = 0;
  for (int p : shape_unchecked) unchecked += shape_checked.count(p) ? 0 : 1;
  const std::string shape_note =
      unchecked == 0 ? ""
      : unchecked == 1 && shape_checked.empty()
          ? "; the page's shape was not checked"
          : "; the shape of " + std::to_string(unchecked) + " page(s) was not checked";
  Print("%d of %d tag%s pass%s%s. %s\n", verdict.tags_passed, verdict.tags_checked,
        verdict.tags_checked == 1 ? "" : "s",
        verdict.tags_warned
            ? (" (" + std::to_string(verdict.tags_warned) + " with warnings)").c_str()
            : "",
        shape_note.c_str(),
        verdict.grade == Grade::kFail   ? "FAIL"
        : verdict.grade == Grade::kWarn ? "PASS with warnings"
                                        : "PASS");
}

void PrintPrintCheck(const SheetRecord& record, const PrintVerdict& verdict) {
  for (const PrintPageResult& r : verdict.images) {
    if (r.page < 0) {
      Print("%s: page not recognised\n", r.image.c_str());
    } else if (r.scan) {
      Print(
          "%s: page %d of %d, scan at %.0f dpi, %d of %zu tags found; scale x %.3f ± %.3f, "
          "y %.3f ± %.3f\n",
          r.image.c_str(), r.page + 1, record.num_pages, r.dpi_x, r.tags_found, r.tags.size(),
          r.scale_x, std::max(0.001, 2 * r.scale_x_error), r.scale_y,
          std::max(0.001, 2 * r.scale_y_error));
    } else if (r.aspect == 0) {
      Print("%s: page %d of %d, photo, %d of %zu tags found\n", r.image.c_str(), r.page + 1,
            record.num_pages, r.tags_found, r.tags.size());
    } else {
      Print(
          "%s: page %d of %d, photo, %d of %zu tags found; aspect x/y %.3f ± %.3f (the size "
          "cannot be told from a photo: scan the page, or measure the scale bar)\n",
          r.image.c_str(), r.page + 1, record.num_pages, r.tags_found, r.tags.size(), r.aspect,
          std::max(0.001, 2 * r.aspect_error));
    }
    for (size_t i = 0; i < r.problems.size(); ++i) {
      Print("  %s: %s\n", r.problem_grades[i] == Grade::kFail ? "FAIL" : "warn",
            r.problems[i].c_str());
    }
    if (r.tags.empty()) continue;
    Print("  %5s %5s %7s %6s %6s %6s %6s  %s\n", "ID", "found", "hamming", "a* gap", "red b*",
          "grn b*", "margin", "verdict");
    for (const PrintTagResult& t : r.tags) {
      const Margins& m = t.colours.margins;
      Print("  %5d %5s %7d %6.1f %6.1f %6.1f %6.1f  %s%s%s\n", t.expected.id,
            t.found ? (t.found_id == t.expected.id ? "yes" : "wrong") : "no", t.hamming, m.a_gap,
            m.red_b_gap, m.green_b_gap, t.margin, GradeName(t.grade),
            t.problems.empty() ? "" : ": ", t.problems.empty() ? "" : t.problems[0].c_str());
      for (size_t i = 1; i < t.problems.size(); ++i) Print("  %50s%s\n", "", t.problems[i].c_str());
    }
  }
  for (int p : verdict.pages_not_seen)
    Print("page %d: no scan or photo shows it (not checked)\n", p + 1);
  PrintPrintSummary(verdict);
}

// "0.5%" or "0.005": a relative tolerance.
std::optional<double> ParseFraction(const std::string& text, std::string* error) {
  std::string number = text;
  const bool percent = !number.empty() && number.back() == '%';
  if (percent) number.pop_back();
  char* end = nullptr;
  const double value = number.empty() ? 0.0 : std::strtod(number.c_str(), &end);
  if (number.empty() || end != number.c_str() + number.size() || !std::isfinite(value)) {
    *error = "'" + text + "' is not a fraction (0.005) or a percentage (0.5%)";
    return std::nullopt;
  }
  return percent ? value / 100.0 : value;
}

// The findings in the command line's terms, in the table, JSON and report alike.
void InCommandLineTerms(PrintVerdict* verdict) {
  for (PrintPageResult& image : verdict->images) {
    for (std::string& problem : image.problems) problem = InFlagTerms(problem);
    for (PrintTagResult& tag : image.tags)
      for (std::string& problem : tag.problems) problem = InFlagTerms(problem);
  }
}

int RunPrintCheck(const VerifyCommandOptions& o) {
  std::string error;
  if (o.sheet.empty()) {
    return Fail("verify",
                "--print needs the sheet that was printed: chromatag verify tags.pdf --print "
                "scan.png (or the sidecar, tags.pdf.json)");
  }
  PrintCheckOptions options;
  options.scans = o.scan || o.scan_dpi > 0;
  options.scan_dpi = o.scan_dpi;
  const auto tolerance = ParseFraction(o.scale_tolerance, &error);
  if (!tolerance) return Fail("verify", "--scale-tolerance: " + error);
  options.max_scale_error = *tolerance;
  if (!o.config.empty() && !LoadDetectorConfig(o.config, &options.detector, &error))
    return Fail("verify", error);
  if (!o.camera_file.empty()) {
    CameraIntrinsics camera;
    if (!LoadCameraFile(o.camera_file, &camera, &error)) return Fail("verify", error);
    options.camera = camera;
  }
  if (!options.IsValid(&error)) return Fail("verify", error);
  std::string report_format;
  if (!o.report.empty()) {
    const std::string ext = LowerExtension(o.report);
    if (ext != ".pdf" && ext != ".png") {
      return Fail("verify", "--report '" + o.report +
                                "': the report is a .pdf or a .png (from its extension)");
    }
    report_format = ext;
  }
  const auto record = ReadPrintedSheet(o.sheet, &error);
  if (!record) return Fail("verify", error);
  auto verdict = CheckPrintFiles(*record, o.prints, options, &error);
  if (!verdict) return Fail("verify", error);
  InCommandLineTerms(&*verdict);
  if (!o.report.empty()) {
    const std::string bytes = report_format == ".pdf" ? RenderPrintReportPdf(*record, *verdict)
                                                      : RenderPrintReportPng(*record, *verdict);
    if (bytes.empty()) {
      return Fail("verify", "--report '" + o.report + "': a PNG report holds at most " +
                                std::to_string(kMaxPngReportImages) +
                                " images; write a .pdf (a page per image)");
    }
    if (!WriteFilesAtomically({{o.report, bytes}}, &error)) return Fail("verify", error);
  }
  if (o.json) {
    std::cout << PrintVerdictJson(*record, *verdict) << "\n";
  } else {
    Print("Printed sheet %s: %s, %zu tag%s of %.1f mm on %d page%s, palette %s\n", o.sheet.c_str(),
          record->family->name().c_str(), record->tags.size(), record->tags.size() == 1 ? "" : "s",
          record->tag_size_mm, record->num_pages, record->num_pages == 1 ? "" : "s",
          record->palette.name.c_str());
    PrintPrintCheck(*record, *verdict);
    if (!o.report.empty()) Print("Report: %s\n", o.report.c_str());
  }
  return verdict->passed() ? kExitOk : kExitFailure;
}

// The stress table, or the JSON document; the exit code.
int Finish(const VerifyCommandOptions& o, const std::string& json,
           const std::vector<TagStress>& stresses, bool passed) {
  if (o.json) {
    std::cout << json << "\n";
  } else {
    PrintStress(stresses);
  }
  return passed ? kExitOk : kExitFailure;
}

// A generated sheet, detected again.
int VerifySheet(const VerifyCommandOptions& o, const VerifyOptions& options) {
  std::string error;
  // The sheet first, so that a missing sheet is named as such (not its sidecar).
  const auto verdict = VerifySheetFile(o.sheet, options, &error);
  if (!verdict) return Fail("verify", error);
  const auto record = ReadSidecar(SidecarPath(o.sheet), &error);
  if (!record) return Fail("verify", error);
  std::vector<TagStress> stresses;
  if (o.stress) {
    std::vector<int> ids;
    for (const auto& tag : record->tags) ids.push_back(tag.id);
    stresses = RunStress(*record->family, ids, record->palette);
  }
  if (o.json)
    return Finish(o, SheetVerdictJson(*verdict, o.sheet, o.stress ? &stresses : nullptr), stresses,
                  verdict->passed);
  Print("Sheet %s: %s, %zu tag%s of %.1f mm on %d page%s, palette %s, at %.0f dpi\n",
        o.sheet.c_str(), record->family->name().c_str(), record->tags.size(),
        record->tags.size() == 1 ? "" : "s", record->tag_size_mm, record->num_pages,
        record->num_pages == 1 ? "" : "s", record->palette.name.c_str(),
        record->format == SheetFormat::kPng ? record->dpi : o.dpi);
  PrintSheet(*verdict);
  return Finish(o, "", stresses, verdict->passed);
}

// Every kept ID of --family rendered and detected again, and the audit.
int VerifyWholeFamily(const VerifyCommandOptions& o, const VerifyOptions& options) {
  std::string error;
  const auto palette = o.palette_file.empty() ? BuiltinPalette(o.palette, &error)
                                              : LoadPaletteFile(o.palette_file, &error);
  if (!palette) return Fail("verify", error);
  const auto verdict = VerifyFamily(o.family, *palette, options, &error);
  if (!verdict) return Fail("verify", error);
  std::vector<TagStress> stresses;
  if (o.stress) {
    auto family = TagFamily::Load(o.family);
    stresses = RunStress(*family, family->kept_ids(), *palette);
  }
  if (o.json)
    return Finish(o, FamilyVerdictJson(o.family, *verdict, o.stress ? &stresses : nullptr),
                  stresses, verdict->passed);
  Print("Every kept %s ID, rendered with palette %s and detected again:\n", o.family.c_str(),
        palette->name.c_str());
  PrintSheet(verdict->sheet);
  PrintAudit(o.family, verdict->audit);
  Print("%s\n", verdict->passed ? "PASS" : "FAIL");
  return Finish(o, "", stresses, verdict->passed);
}

int RunVerify(const VerifyCommandOptions& o) {
  std::string error;
  if (!o.prints.empty()) {
    if (o.all || o.stress || !o.family.empty())
      return Fail(
          "verify",
          "--print checks a printed sheet; it does not combine with --family, --all or --stress");
    return RunPrintCheck(o);
  }
  if (o.scan || o.scan_dpi > 0 || !o.config.empty() || !o.camera_file.empty() || !o.report.empty())
    return Fail("verify",
                "--scan, --scan-dpi, --config, --camera and --report go with --print (scans or "
                "photos of the printed sheet)");
  VerifyOptions options;
  options.dpi = o.dpi;
  const auto tolerance = ParseLength(o.tolerance, &error);
  if (!tolerance) return Fail("verify", error);
  options.max_position_error_mm = tolerance->mm;
  if (!options.IsValid(&error)) return Fail("verify", error);
  if (o.sheet.empty() == !(o.all && !o.family.empty())) {
    return Fail("verify",
                "give a sheet (chromatag verify tags.pdf) or a family (--family 16h5 --all)");
  }
  return o.sheet.empty() ? VerifyWholeFamily(o, options) : VerifySheet(o, options);
}

}  // namespace

void RegisterVerify(CLI::App& app, Action* action) {
  auto o = std::make_shared<VerifyCommandOptions>();
  CLI::App* c = app.add_subcommand(
      "verify", "Check that every tag of a generated sheet (or a whole family) decodes");
  c->add_option("sheet", o->sheet,
                "A sheet written by 'generate' (.pdf, .svg, .png), or give it with --sheet");
  c->add_option("--family", o->family, "With --all: check this whole family")
      ->transform(FamilyPrefix())
      ->check(CLI::IsMember(TagFamily::Names()));
  c->add_flag("--all", o->all, "Render every kept ID of --family and audit the family");
  c->add_flag("--stress", o->stress,
              "Also view every tag through camera conditions: size, tilt, blur, noise, JPEG, "
              "casts, Bayer");
  c->add_option("--dpi", o->dpi, "Resolution PDF and SVG pages are rasterised at")
      ->capture_default_str();
  c->add_option("--tolerance", o->tolerance, "Largest accepted corner position error")
      ->capture_default_str();
  auto* palette =
      c->add_option("--palette", o->palette, "Palette for --all")->capture_default_str();
  c->add_option("--palette-file", o->palette_file, "Palette file for --all")->excludes(palette);
  c->add_flag("--json", o->json, "Print one JSON object");
  const char* kPrintGroup = "Checking a print (--print)";
  c->add_option("--print", o->prints,
                "Scans or photos of the printed sheet's pages: check the print itself")
      ->group(kPrintGroup)
      ->expected(1, -1);
  c->add_option("--sheet", o->sheet,
                "The sheet (.pdf, .svg, .png; its sidecar beside it), or with --print its "
                "sidecar .json");
  c->add_flag("--scan", o->scan,
              "The images are flatbed scans: check the printed size (resolution from the file)")
      ->group(kPrintGroup);
  c->add_option("--scan-dpi", o->scan_dpi, "The scans' resolution, 50-4800, when the files lack it")
      ->check(CLI::Range(50.0, 4800.0))
      ->group(kPrintGroup);
  c->add_option("--scale-tolerance", o->scale_tolerance, "Largest accepted scale error of a scan")
      ->capture_default_str()
      ->group(kPrintGroup);
  c->add_option("--config", o->config,
                "Detector config (from chromatag calibrate) to judge the shades by")
      ->group(kPrintGroup);
  c->add_option("--camera", o->camera_file, "Camera file for photos (OpenCV, ROS, Kalibr)")
      ->group(kPrintGroup);
  c->add_option("--report", o->report, "Write a drawn report: .pdf (a page per image) or .png")
      ->group(kPrintGroup);
  c->callback([o, action] { *action = [o] { return RunVerify(*o); }; });
}

}  // namespace chromatag::cli
