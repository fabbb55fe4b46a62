// Tag ID lists as users type them: "0-9,12,20-27".
#ifndef CHROMATAG_GENERATOR_ID_LIST_H_
#define CHROMATAG_GENERATOR_ID_LIST_H_

#include <optional>
#include <string>
#include <vector>

#include "chromatag/families/family.h"

namespace chromatag {

// Parses comma-separated IDs and inclusive ranges, in the order given, and
// checks each against `family`. Refuses (nullopt, *error) syntax errors,
// reversed ranges, duplicates, and IDs the family does not keep, naming the
// first offending ID and why it is not valid (e.g. "16h5 ID 5 is rejected:
// red cells are all bit 1 ...").
std::optional<std::vector<int>> ParseIdList(const std::string& text, const TagFamily& family,
                                            std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_ID_LIST_H_
