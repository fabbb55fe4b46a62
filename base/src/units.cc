#include "chromatag/base/units.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>

namespace chromatag {
namespace {

struct Unit {
  const char* name;
  double mm;
};
constexpr Unit kUnits[] = {{"mm", 1.0}, {"cm", 10.0}, {"m", 1000.0}, {"in", 25.4}};

struct NamedPage {
  const char* name;
  double width_mm, height_mm;
};
// ISO 216 and ANSI sizes, portrait.
constexpr NamedPage kPages[] = {
    {"a4", 210.0, 297.0}, {"a3", 297.0, 420.0}, {"letter", 215.9, 279.4}, {"legal", 215.9, 355.6}};

std::string Lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

std::string Trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// Splits "12.5 mm" into 12.5 and "mm"; false if there is no leading number.
bool SplitNumber(const std::string& text, double* value, std::string* rest) {
  const char* begin = text.c_str();
  char* end = nullptr;
  *value = std::strtod(begin, &end);
  if (end == begin) return false;
  *rest = Trim(end);
  return true;
}

const Unit* FindUnit(const std::string& name) {
  for (const auto& unit : kUnits) {
    if (name == unit.name) return &unit;
  }
  return nullptr;
}

}  // namespace

std::optional<Length> ParseLength(const std::string& input, std::string* error) {
  auto fail = [&](const std::string& what) -> std::optional<Length> {
    if (error) *error = "invalid length '" + input + "': " + what;
    return std::nullopt;
  };
  const std::string text = Lower(Trim(input));
  double value = 0.0;
  std::string unit_name;
  if (!SplitNumber(text, &value, &unit_name)) {
    return fail("expected a number and a unit, e.g. 40mm (units: mm, cm, m, in)");
  }
  if (unit_name.empty()) return fail("the unit is missing (units: mm, cm, m, in)");
  const Unit* unit = FindUnit(unit_name);
  if (unit == nullptr) return fail("unknown unit '" + unit_name + "' (units: mm, cm, m, in)");
  if (!std::isfinite(value) || value <= 0.0) return fail("the length must be greater than zero");
  // Checked again in millimetres: 1e308m is finite, a thousand times it is not.
  const double mm = value * unit->mm;
  if (!std::isfinite(mm) || mm <= 0.0) return fail("the length is too large");
  return Length{mm};
}

std::optional<PageSize> ParsePageSize(const std::string& input, std::string* error) {
  const std::string text = Lower(Trim(input));
  for (const auto& page : kPages) {
    if (text == page.name) return PageSize{page.name, page.width_mm, page.height_mm};
    for (const char* orientation : {"landscape", "portrait"}) {
      for (const char separator : {'-', ' '}) {
        if (text != std::string(page.name) + separator + orientation) continue;
        const bool landscape = orientation[0] == 'l';
        const double shorter = std::min(page.width_mm, page.height_mm),
                     longer = std::max(page.width_mm, page.height_mm);
        return PageSize{std::string(page.name) + " " + orientation, landscape ? longer : shorter,
                        landscape ? shorter : longer, /*may_turn=*/false};
      }
    }
  }
  auto fail = [&](const std::string& what) -> std::optional<PageSize> {
    if (error) {
      *error = "invalid page '" + input + "': " + what +
               " (valid: a4, a3, letter, legal, each also as a4-landscape or a4-portrait, or WxH "
               "with a unit such as 210x297mm)";
    }
    return std::nullopt;
  };
  const auto x = text.find('x');
  if (x == std::string::npos) return fail("unknown page size");
  double width = 0.0;
  std::string width_rest;
  if (!SplitNumber(text.substr(0, x), &width, &width_rest)) return fail("no width before 'x'");
  std::string length_error;
  const auto height = ParseLength(text.substr(x + 1), &length_error);
  if (!height) return fail("bad height");
  // The unit after the height applies to both, unless the width has its own.
  std::string unit_name = width_rest;
  if (unit_name.empty()) {
    double unused;
    SplitNumber(text.substr(x + 1), &unused, &unit_name);
  }
  const Unit* unit = FindUnit(unit_name);
  if (unit == nullptr) return fail("unknown unit '" + unit_name + "'");
  if (!std::isfinite(width) || width <= 0.0) return fail("the width must be greater than zero");
  if (width * unit->mm > kMaxPageSideMm || height->mm > kMaxPageSideMm)
    return fail("a page side may be at most 10 m");
  return PageSize{"custom", width * unit->mm, height->mm};
}

}  // namespace chromatag
