// The JSON documents of `chromatag verify --json` for a sheet and for a
// family (sheet_check.h, family_check.h) and of the stress views
// (stress.h): one writer each. The print check's is print_json.cc.
#include <nlohmann/json.hpp>

#include "chromatag/verify/family_check.h"
#include "chromatag/verify/sheet_check.h"
#include "chromatag/verify/stress.h"

namespace chromatag {
namespace {

using Json = nlohmann::ordered_json;

Json SheetObject(const SheetVerdict& verdict) {
  Json tags = Json::array();
  for (const auto& t : verdict.tags) {
    tags.push_back({{"id", t.expected.id},
                    {"page", t.expected.page + 1},
                    {"times_found", t.times_found},
                    {"found_id", t.found_id},
                    {"hamming", t.hamming},
                    {"margin", t.margin},
                    {"position_error_mm", t.position_error_mm},
                    {"passed", t.passed},
                    {"problem", t.problem}});
  }
  Json unexpected = Json::array();
  for (const auto& u : verdict.unexpected) {
    unexpected.push_back({{"page", u.page + 1},
                          {"family", u.family},
                          {"id", u.id},
                          {"center_mm", {u.center_mm[0], u.center_mm[1]}}});
  }
  return {{"passed", verdict.passed},
          {"tags_passed", verdict.tags_passed},
          {"tags", tags},
          {"unexpected", unexpected},
          {"file_problems", verdict.file_problems}};
}

std::string Dump(const Json& json) {
  // A path or a problem that quotes bytes that are not UTF-8: U+FFFD.
  return json.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace

std::string StressJson(const std::vector<TagStress>& stresses) {
  Json all = Json::array();
  for (const auto& s : stresses) {
    Json conditions = Json::object();
    for (const auto& c : s.conditions) conditions[c.condition] = c.decoded;
    all.push_back({{"id", s.id},
                   {"smallest_size_px", s.smallest_size_px},
                   {"largest_tilt_deg", s.largest_tilt_deg},
                   {"conditions", conditions}});
  }
  return Dump(all);
}

std::string SheetVerdictJson(const SheetVerdict& verdict, const std::string& sheet,
                             const std::vector<TagStress>* stress) {
  Json out = SheetObject(verdict);
  out["sheet"] = sheet;
  if (stress) out["stress"] = Json::parse(StressJson(*stress));
  return Dump(out);
}

std::string FamilyVerdictJson(const std::string& family, const FamilyVerdict& verdict,
                              const std::vector<TagStress>* stress) {
  Json out = SheetObject(verdict.sheet);
  out["family"] = family;
  // The audit's own writer; parsed back so that it nests in this document.
  out["audit"] = Json::parse(FamilyAuditJson(verdict.audit));
  out["passed"] = verdict.passed;
  if (stress) out["stress"] = Json::parse(StressJson(*stress));
  return Dump(out);
}

}  // namespace chromatag
