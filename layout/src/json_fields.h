// Reading the members of the project's own JSON files (sheet and
// calibration sidecars): each accessor checks presence, type and, for
// integers, range before any conversion, and throws FieldError with a
// message that names the member. The readers catch it once and turn it into
// their one error line.
#ifndef CHROMATAG_LAYOUT_SRC_JSON_FIELDS_H_
#define CHROMATAG_LAYOUT_SRC_JSON_FIELDS_H_

#include <array>
#include <nlohmann/json.hpp>
#include <string>

namespace chromatag::json_fields {

struct FieldError {
  std::string message;
};

// The member `key` of `object`; FieldError when `object` is not an object or lacks it.
const nlohmann::json& Member(const nlohmann::json& object, const char* key);
// A finite number.
double Number(const nlohmann::json& object, const char* key);
// An integer in [lo, hi] (a number with no fraction), checked before the cast.
int Integer(const nlohmann::json& object, const char* key, int lo, int hi);
std::string String(const nlohmann::json& object, const char* key);
// [x, y] in mm, finite.
std::array<double, 2> Point(const nlohmann::json& value);

}  // namespace chromatag::json_fields

#endif  // CHROMATAG_LAYOUT_SRC_JSON_FIELDS_H_
