#include "chromatag/families/input_file.h"

#include <algorithm>
#include <climits>
#include <cstring>
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

bool IsValidUtf8(const std::string& text) {
  size_t i = 0;
  while (i < text.size()) {
    const auto c = static_cast<unsigned char>(text[i]);
    int extra = 0;
    uint32_t code = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xe0) == 0xc0) {
      extra = 1;
      code = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      extra = 2;
      code = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      extra = 3;
      code = c & 0x07;
    } else {
      return false;
    }
    if (i + extra >= text.size()) return false;  // Cut short.
    for (int k = 1; k <= extra; ++k) {
      const auto next = static_cast<unsigned char>(text[i + k]);
      if ((next & 0xc0) != 0x80) return false;
      code = (code << 6) | (next & 0x3f);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not UTF-8.
    static constexpr uint32_t kMin[4] = {0, 0x80, 0x800, 0x10000};
    if (code < kMin[extra] || code > 0x10ffff || (code >= 0xd800 && code <= 0xdfff)) return false;
    i += static_cast<size_t>(extra) + 1;
  }
  return true;
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

bool ImageHeaderSize(const std::string& path, int* width, int* height) {
  std::ifstream in(path, std::ios::binary);
  unsigned char head[26] = {};
  if (!in.read(reinterpret_cast<char*>(head), sizeof head)) return false;
  auto be32 = [](const unsigned char* p) {
    return static_cast<int64_t>(p[0]) << 24 | p[1] << 16 | p[2] << 8 | p[3];
  };
  if (std::memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0 && std::memcmp(head + 12, "IHDR", 4) == 0) {
    const int64_t w = be32(head + 16), h = be32(head + 20);
    *width = static_cast<int>(std::min<int64_t>(w, INT32_MAX));
    *height = static_cast<int>(std::min<int64_t>(h, INT32_MAX));
    return true;
  }
  if (head[0] != 0xff || head[1] != 0xd8) return false;
  // JPEG: walk the markers to the first start of frame (SOF0-SOF15 but the
  // DHT, JPG and DAC markers C4, C8, CC).
  in.seekg(2);
  for (int markers = 0; markers < 1000; ++markers) {
    unsigned char m[4];
    if (!in.read(reinterpret_cast<char*>(m), 4) || m[0] != 0xff) return false;
    const int length = m[2] << 8 | m[3];
    if (m[1] >= 0xc0 && m[1] <= 0xcf && m[1] != 0xc4 && m[1] != 0xc8 && m[1] != 0xcc) {
      unsigned char sof[5];
      if (!in.read(reinterpret_cast<char*>(sof), 5)) return false;
      *height = sof[1] << 8 | sof[2];
      *width = sof[3] << 8 | sof[4];
      return true;
    }
    if (length < 2) return false;
    in.seekg(length - 2, std::ios::cur);
  }
  return false;
}

}  // namespace chromatag
