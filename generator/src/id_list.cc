#include "chromatag/generator/id_list.h"

#include <cctype>
#include <set>
#include <sstream>

namespace chromatag {
namespace {

// A whole non-negative decimal number, nothing else.
bool ParseNumber(const std::string& text, int* value) {
  if (text.empty() || text.size() > 6) return false;
  for (char c : text) {
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  }
  *value = std::stoi(text);
  return true;
}

std::string Strip(const std::string& text) {
  const auto first = text.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(' ') - first + 1);
}

}  // namespace

std::optional<std::vector<int>> ParseIdList(const std::string& text, const TagFamily& family,
                                            std::string* error) {
  auto fail = [&](const std::string& message) -> std::optional<std::vector<int>> {
    if (error) *error = message;
    return std::nullopt;
  };
  const std::string syntax = " (expected IDs and ranges such as 0-9,12,20-27)";
  std::vector<int> ids;
  std::set<int> seen;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ',')) {
    item = Strip(item);
    int first = 0, last = 0;
    const auto dash = item.find('-');
    if (dash == std::string::npos) {
      if (!ParseNumber(item, &first)) return fail("invalid ID '" + item + "'" + syntax);
      last = first;
    } else if (!ParseNumber(Strip(item.substr(0, dash)), &first) ||
               !ParseNumber(Strip(item.substr(dash + 1)), &last)) {
      return fail("invalid ID range '" + item + "'" + syntax);
    } else if (last < first) {
      return fail("ID range '" + item + "' runs backwards");
    }
    for (int id = first; id <= last; ++id) {
      std::string why;
      if (!family.IsValidId(id, &why)) return fail(why);
      if (!seen.insert(id).second) return fail("ID " + std::to_string(id) + " is listed twice");
      ids.push_back(id);
    }
  }
  if (ids.empty()) return fail("no IDs given" + syntax);
  return ids;
}

}  // namespace chromatag
