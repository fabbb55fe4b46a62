#include "chromatag/families/input_file.h"

#include <filesystem>
#include <fstream>

namespace chromatag {

std::optional<std::string> ReadInputFile(const std::string& path, const std::string& kind,
                                         std::uintmax_t max_bytes, std::string* error) {
  namespace fs = std::filesystem;
  auto fail = [&](const std::string& why) -> std::optional<std::string> {
    if (error) *error = "cannot read " + kind + " '" + path + "': " + why;
    return std::nullopt;
  };
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return fail("no such file");
  if (!fs::is_regular_file(status)) return fail("not a regular file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) return fail(ec.message());
  if (size > max_bytes) {
    return fail(std::to_string(size) + " bytes, over the limit of " + std::to_string(max_bytes));
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) return fail("cannot open it");
  std::string text(static_cast<size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  if (static_cast<std::uintmax_t>(in.gcount()) != size) return fail("read error");
  return text;
}

bool JsonDeeperThan(const std::string& json_text, int max_depth) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : json_text) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_depth) return true;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return false;
}

}  // namespace chromatag
