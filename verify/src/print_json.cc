// verify --print's verdict as JSON (print_check.h), for the CLI's --json
// and the Python module.
#include <nlohmann/json.hpp>

#include "chromatag/verify/print_check.h"

namespace chromatag {
namespace {

using Json = nlohmann::ordered_json;

Json Grades(const std::vector<Grade>& grades) {
  Json out = Json::array();
  for (Grade g : grades) out.push_back(GradeName(g));
  return out;
}

Json ShadesJson(const PrintedShades& c) {
  Json shades = Json::object();
  if (!c.measured) return shades;
  for (int s = 0; s < 4; ++s) {
    const Lab& lab = c.shades[s].lab;
    shades[ShadeName(static_cast<Shade>(s))] = {lab.L, lab.a, lab.b};
  }
  const Margins& m = c.margins;
  return {{"lab", shades},
          {"a_gap", m.a_gap},
          {"red_b_gap", m.red_b_gap},
          {"green_b_gap", m.green_b_gap},
          {"red_decision", m.red_decision},
          {"green_decision", m.green_decision}};
}

Json TagJson(const PrintTagResult& t, bool scan) {
  Json tag = {{"id", t.expected.id},
              {"grade", GradeName(t.grade)},
              {"found", t.found},
              {"found_id", t.found_id},
              {"hamming", t.hamming},
              {"margin", t.margin},
              {"position_error_mm", t.position_error_mm},
              {"shades", ShadesJson(t.colours)},
              {"problems", t.problems},
              {"problem_grades", Grades(t.problem_grades)}};
  if (scan) tag["size_mm"] = t.size_mm;
  return tag;
}

Json UndecodedJson(const std::vector<UndecodedCandidate>& candidates) {
  Json undecoded = Json::array();
  for (const UndecodedCandidate& u : candidates) {
    Json corners = Json::array();
    for (const cv::Point2d& p : u.corners_px) corners.push_back({p.x, p.y});
    undecoded.push_back({{"corners_px", corners},
                         {"red_b_split", u.red_b_split},
                         {"green_b_split", u.green_b_split},
                         {"a_gap", u.a_gap}});
  }
  return undecoded;
}

Json ImageJson(const PrintPageResult& r) {
  Json image = {{"image", r.image},
                {"page", r.page >= 0 ? Json(r.page + 1) : Json(nullptr)},
                {"kind", r.scan ? "scan" : "photo"},
                {"grade", GradeName(r.grade)},
                {"tags_found", r.tags_found},
                {"rms_mm", r.rms_mm},
                {"geometry_checked", r.geometry_checked}};
  if (r.scan) {
    image["dpi"] = {r.dpi_x, r.dpi_y};
    image["scale"] = {{"x", r.scale_x},
                      {"y", r.scale_y},
                      {"x_standard_error", r.scale_x_error},
                      {"y_standard_error", r.scale_y_error},
                      {"skew_deg", r.skew_deg}};
  } else {
    image["aspect"] = {{"x_over_y", r.aspect > 0 ? Json(r.aspect) : Json(nullptr)},
                       {"standard_error", r.aspect_error},
                       {"focal_px", r.focal_px},
                       {"focal_source", r.focal_source}};
  }
  Json unexpected = Json::array();
  for (const auto& u : r.unexpected) {
    unexpected.push_back(
        {{"family", u.family}, {"id", u.id}, {"center_mm", {u.center_mm[0], u.center_mm[1]}}});
  }
  Json tags = Json::array();
  for (const PrintTagResult& t : r.tags) tags.push_back(TagJson(t, r.scan));
  image["problems"] = r.problems;
  image["problem_grades"] = Grades(r.problem_grades);
  image["undecoded"] = UndecodedJson(r.undecoded);
  image["unexpected"] = unexpected;
  image["tags"] = tags;
  return image;
}

Json ToJson(const SheetRecord& record, const PrintVerdict& verdict) {
  Json images = Json::array();
  for (const PrintPageResult& r : verdict.images) images.push_back(ImageJson(r));
  Json not_seen = Json::array();
  for (int p : verdict.pages_not_seen) not_seen.push_back(p + 1);
  return {{"sheet", record.sidecar_path},       {"grade", GradeName(verdict.grade)},
          {"passed", verdict.passed()},         {"tags_checked", verdict.tags_checked},
          {"tags_passed", verdict.tags_passed}, {"tags_warned", verdict.tags_warned},
          {"pages_not_seen", not_seen},         {"images", images}};
}

}  // namespace

std::string PrintVerdictJson(const SheetRecord& record, const PrintVerdict& verdict) {
  return ToJson(record, verdict).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace chromatag
