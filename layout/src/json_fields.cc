#include "json_fields.h"

#include <cmath>

namespace chromatag::json_fields {

using Json = nlohmann::json;

const Json& Member(const Json& object, const char* key) {
  if (!object.is_object() || !object.contains(key))
    throw FieldError{std::string("missing \"") + key + "\""};
  return object.at(key);
}

double Number(const Json& object, const char* key) {
  const Json& value = Member(object, key);
  if (!value.is_number() || !std::isfinite(value.get<double>()))
    throw FieldError{std::string("\"") + key + "\" must be a number"};
  return value.get<double>();
}

int Integer(const Json& object, const char* key, int lo, int hi) {
  const double value = Number(object, key);
  if (value != std::floor(value) || value < lo || value > hi) {
    throw FieldError{std::string("\"") + key + "\" must be an integer in [" + std::to_string(lo) +
                     ", " + std::to_string(hi) + "]"};
  }
  return static_cast<int>(value);
}

std::string String(const Json& object, const char* key) {
  const Json& value = Member(object, key);
  if (!value.is_string()) throw FieldError{std::string("\"") + key + "\" must be a string"};
  return value.get<std::string>();
}

std::array<double, 2> Point(const Json& value) {
  if (!value.is_array() || value.size() != 2 || !value[0].is_number() || !value[1].is_number() ||
      !std::isfinite(value[0].get<double>()) || !std::isfinite(value[1].get<double>())) {
    throw FieldError{"a position must be [x, y] in mm"};
  }
  return {value[0].get<double>(), value[1].get<double>()};
}

}  // namespace chromatag::json_fields
