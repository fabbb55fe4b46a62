// Physical lengths and page sizes as users type them: "40mm", "1.5in",
// "a4", "210x297mm"; the tag and sheet renderer takes its sizes in these.
#ifndef CHROMATAG_BASE_UNITS_H_
#define CHROMATAG_BASE_UNITS_H_

#include <optional>
#include <string>

namespace chromatag {

// A length in millimetres, the unit of the generator's layouts and sidecars.
struct Length {
  double mm = 0.0;
};

// Parses a positive number followed by a unit: mm, cm, m or in (no space
// needed, "40mm", "4 cm", "1.5in"). Refuses (nullopt, *error) a missing or
// unknown unit, a zero, negative or non-finite value.
std::optional<Length> ParseLength(const std::string& text, std::string* error = nullptr);

// The largest page side the toolkit lays out or draws (10 m; A0 is 1.19 m):
// beyond it sizes are typing mistakes, and counts of tags overflow.
inline constexpr double kMaxPageSideMm = 10000.0;

struct PageSize {
  std::string name;  // "a4", "a4 landscape", or "custom" for WxH.
  double width_mm = 0.0;
  double height_mm = 0.0;
  // False when the orientation was asked for ("a4-landscape"): a layout
  // that would fit the page turned may not turn it.
  bool may_turn = true;
};

// "a4", "a3", "letter", "legal" (any case), each also with "-landscape" or
// "-portrait" (or a space before it) to fix the orientation, or "WxH" with a
// unit after the height, e.g. "210x297mm", "8.5x11in".
std::optional<PageSize> ParsePageSize(const std::string& text, std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_BASE_UNITS_H_
