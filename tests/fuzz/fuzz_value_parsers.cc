// The generator's parsers of what users type on the command line (--size,
// --page, --ids) on arbitrary text, each held to what its header promises:
// a refusal always says why, and what is accepted is usable as it is (a
// length finite and positive, a page within kMaxPageSideMm, IDs the family
// keeps, each once) since the layout code downstream trusts it.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>

#include "chromatag/base/units.h"
#include "chromatag/families/family.h"
#include "chromatag/generator/id_list.h"

namespace {

// An abort with the input's parser and the broken promise, for the report.
void Check(bool ok, const char* parser, const char* promise, const std::string& text) {
  if (ok) return;
  std::fprintf(stderr, "%s broke its contract (%s) on '%s'\n", parser, promise, text.c_str());
  std::abort();
}

void CheckLength(const std::string& text) {
  std::string error;
  const auto length = chromatag::ParseLength(text, &error);
  Check(length.has_value() == chromatag::ParseLength(text).has_value(), "ParseLength",
        "the same answer without an error string", text);
  if (!length) {
    Check(!error.empty(), "ParseLength", "a refusal says why", text);
    return;
  }
  Check(std::isfinite(length->mm) && length->mm > 0, "ParseLength", "finite and positive mm", text);
}

// A named page, as it was named ("a4") or with the orientation asked for
// ("a4 landscape": the longer side across, never turned).
bool IsNamedPage(const chromatag::PageSize& page) {
  for (const std::string name : {"a4", "a3", "letter", "legal"}) {
    if (page.name == name) return page.may_turn;
    if (page.name == name + " landscape") return !page.may_turn && page.width_mm > page.height_mm;
    if (page.name == name + " portrait") return !page.may_turn && page.width_mm < page.height_mm;
  }
  return false;
}

void CheckPageSize(const std::string& text) {
  std::string error;
  const auto page = chromatag::ParsePageSize(text, &error);
  Check(page.has_value() == chromatag::ParsePageSize(text).has_value(), "ParsePageSize",
        "the same answer without an error string", text);
  if (!page) {
    Check(!error.empty(), "ParsePageSize", "a refusal says why", text);
    return;
  }
  Check((page->name == "custom" && page->may_turn) || IsNamedPage(*page), "ParsePageSize",
        "a known name (its orientation as named) or custom", text);
  for (double side : {page->width_mm, page->height_mm}) {
    Check(std::isfinite(side) && side > 0 && side <= chromatag::kMaxPageSideMm, "ParsePageSize",
          "sides in (0, kMaxPageSideMm] mm", text);
  }
}

void CheckIdList(const std::string& text, const chromatag::TagFamily& family) {
  std::string error;
  const auto ids = chromatag::ParseIdList(text, family, &error);
  Check(ids.has_value() == chromatag::ParseIdList(text, family).has_value(), "ParseIdList",
        "the same answer without an error string", text);
  if (!ids) {
    Check(!error.empty(), "ParseIdList", "a refusal says why", text);
    return;
  }
  Check(!ids->empty(), "ParseIdList", "at least one ID", text);
  std::set<int> seen;
  for (int id : *ids) {
    Check(id >= 0 && id < family.num_apriltag_ids() && family.IsValidId(id), "ParseIdList",
          "kept IDs of the family only", text);
    Check(seen.insert(id).second, "ParseIdList", "no ID twice", text);
  }
  // The ranges FormatIdRanges writes for them read back as the same IDs.
  const auto again =
      chromatag::ParseIdList(chromatag::FormatIdRanges({seen.begin(), seen.end()}), family);
  Check(again && std::set<int>(again->begin(), again->end()) == seen, "ParseIdList",
        "FormatIdRanges of its IDs reads back", text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const auto family_16h5 = chromatag::TagFamily::Load("16h5");
  static const auto family_36h11 = chromatag::TagFamily::Load("36h11");
  const std::string text(reinterpret_cast<const char*>(data), size);
  CheckLength(text);
  CheckPageSize(text);
  CheckIdList(text, *family_16h5);
  CheckIdList(text, *family_36h11);
  return 0;
}
