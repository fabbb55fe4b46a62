// FamilyAuditJson (audit.h): the one writer of a family audit's JSON.
#include <nlohmann/json.hpp>

#include "chromatag/families/audit.h"

namespace chromatag {

std::string FamilyAuditJson(const FamilyAudit& audit) {
  using Json = nlohmann::ordered_json;
  Json pairs = Json::array();
  for (const auto& p : audit.closest_pairs) {
    pairs.push_back(
        {{"id_a", p.id_a}, {"id_b", p.id_b}, {"rotation", p.rotation}, {"distance", p.distance}});
  }
  Json flips = Json::array();
  for (const auto& f : audit.flips) {
    flips.push_back({{"flips", f.flips},
                     {"exhaustive", f.exhaustive},
                     {"trials", f.trials},
                     {"correct", f.correct},
                     {"wrong_id", f.wrong_id},
                     {"rejected", f.rejected}});
  }
  const Json out = {{"codes", audit.num_codes},
                    {"min_distance", audit.min_distance},
                    {"radius", audit.radius},
                    {"distance_histogram", audit.histogram},
                    {"closest_pairs", pairs},
                    {"bit_flips", flips},
                    {"decoding_safe", audit.DecodingIsSafe()}};
  return out.dump();
}

}  // namespace chromatag
