#include "chromatag/base/input_file.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <tuple>

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

namespace {

// Reads `n` bytes at `offset` of an image file or buffer; false past its end.
using ReadAt = std::function<bool(uint64_t offset, size_t n, unsigned char* out)>;

uint32_t Be16(const unsigned char* p) { return uint32_t{p[0]} << 8 | p[1]; }
uint32_t Le16(const unsigned char* p) { return uint32_t{p[1]} << 8 | p[0]; }
uint32_t Be32(const unsigned char* p) { return Be16(p) << 16 | Be16(p + 2); }
uint32_t Le32(const unsigned char* p) { return Le16(p + 2) << 16 | Le16(p); }
uint64_t Le64(const unsigned char* p) { return uint64_t{Le32(p + 4)} << 32 | Le32(p); }
uint64_t Be64(const unsigned char* p) { return uint64_t{Be32(p)} << 32 | Be32(p + 4); }

// JPEG: the markers after SOI, found as libjpeg finds them (any bytes up to
// an 0xFF, any number of 0xFF fill bytes, and FF 00 taken as stray data,
// not a marker), up to the first start of frame (SOF0-SOF15 but DHT C4, JPG
// C8 and DAC CC). Bounded by the file: every step moves forward.
bool JpegSize(const ReadAt& read, ImageSize* size) {
  uint64_t at = 2;
  unsigned char b[9];
  for (;;) {
    unsigned marker = 0;
    while (marker == 0) {
      do {
        if (!read(at++, 1, b)) return false;
      } while (b[0] != 0xff);
      do {
        if (!read(at++, 1, b)) return false;
      } while (b[0] == 0xff);
      marker = b[0];
    }
    if (marker == 0x01 || (marker >= 0xd0 && marker <= 0xd7)) continue;     // No length.
    if (marker == 0xd9 || marker == 0xda || !read(at, 2, b)) return false;  // No frame.
    const uint32_t length = Be16(b);
    if (length < 2) return false;
    if (marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc) {
      if (!read(at + 2, 5, b)) return false;
      size->height = Be16(b + 1);
      size->width = Be16(b + 3);
      return true;
    }
    at += length;
  }
}

// TIFF and BigTIFF, either byte order: ImageWidth (256) and ImageLength
// (257) of the first image file directory (the page OpenCV reads).
bool TiffSize(const ReadAt& read, const unsigned char* head, ImageSize* size) {
  const bool little = head[0] == 'I';
  auto u16 = [&](const unsigned char* p) { return little ? Le16(p) : Be16(p); };
  auto u32 = [&](const unsigned char* p) { return little ? Le32(p) : Be32(p); };
  auto u64 = [&](const unsigned char* p) { return little ? Le64(p) : Be64(p); };
  const uint32_t version = u16(head + 2);
  if (version != 42 && version != 43) return false;
  const bool big = version == 43;
  unsigned char b[20] = {};
  uint64_t ifd = 0, entries = 0;
  if (big) {
    if (!read(8, 8, b)) return false;
    ifd = u64(b);
    if (!read(ifd, 8, b)) return false;
    entries = u64(b);
  } else {
    ifd = u32(head + 4);
    if (!read(ifd, 2, b)) return false;
    entries = u16(b);
  }
  const size_t entry_size = big ? 20 : 12;
  const uint64_t first = ifd + (big ? 8 : 2);
  bool have_width = false, have_height = false;
  for (uint64_t e = 0; e < entries && e < 4096 && !(have_width && have_height); ++e) {
    if (!read(first + e * entry_size, entry_size, b)) return false;
    const uint32_t tag = u16(b), type = u16(b + 2);
    // The first ImageWidth and ImageLength count, as libtiff reads them;
    // an entry of a type that holds no size is refused, not passed over.
    if ((tag != 256 || have_width) && (tag != 257 || have_height)) continue;
    const unsigned char* value = b + (big ? 12 : 8);
    uint64_t v = 0;
    if (type == 1) {
      v = value[0];  // BYTE
    } else if (type == 3 || type == 8) {
      v = u16(value);  // SHORT, SSHORT (a negative one reads as huge)
    } else if (type == 4 || type == 9) {
      v = u32(value);  // LONG, SLONG
    } else if (type == 16 && big) {
      v = u64(value);  // LONG8
    } else {
      return false;
    }
    (tag == 256 ? size->width : size->height) = v;
    (tag == 256 ? have_width : have_height) = true;
  }
  return have_width && have_height;
}

// PNM (P1-P6), PFM (PF, Pf): width and height after the magic, separated by
// whitespace and '#' comments; PAM (P7): its WIDTH and HEIGHT lines.
bool PnmSize(const ReadAt& read, ImageSize* size) {
  unsigned char head[1024] = {};
  size_t n = 0;
  while (n < sizeof head && read(n, 1, head + n)) ++n;
  const std::string text(reinterpret_cast<char*>(head), n);
  if (text[1] == '7') {
    // Header lines up to ENDHDR, as OpenCV reads them: leading whitespace,
    // a keyword, whitespace, a value; WIDTH and HEIGHT once each.
    bool have_width = false, have_height = false;
    size_t at = 2;
    while (at < n) {
      const size_t end = text.find_first_of("\r\n", at);
      if (end == std::string::npos) return false;  // Past the 1 KiB read: refused.
      std::string line = text.substr(at, end - at);
      at = end + 1;
      const size_t first = line.find_first_not_of(" \t");
      if (first == std::string::npos || line[first] == '#') continue;
      line = line.substr(first);
      if (line.rfind("ENDHDR", 0) == 0) return have_width && have_height;
      for (const auto& [key, value, seen] :
           {std::make_tuple("WIDTH", &size->width, &have_width),
            std::make_tuple("HEIGHT", &size->height, &have_height)}) {
        const size_t length = std::strlen(key);
        if (line.rfind(key, 0) != 0 || line.size() == length ||
            !std::isspace(static_cast<unsigned char>(line[length])))
          continue;
        if (*seen) return false;
        char* stop = nullptr;
        const char* digits = line.c_str() + length;
        const unsigned long long v = std::strtoull(digits, &stop, 10);
        if (stop == digits) return false;
        *value = v;
        *seen = true;
      }
    }
    return false;
  }
  size_t at = 2;
  uint64_t values[2];
  for (uint64_t& value : values) {
    for (;;) {
      while (at < n && std::isspace(static_cast<unsigned char>(text[at]))) ++at;
      if (at < n && text[at] == '#') {  // To the end of the line, \n or \r (as OpenCV).
        while (at < n && text[at] != '\n' && text[at] != '\r') ++at;
        continue;
      }
      break;
    }
    if (at >= n || !std::isdigit(static_cast<unsigned char>(text[at]))) return false;
    value = 0;
    for (; at < n && std::isdigit(static_cast<unsigned char>(text[at])); ++at) {
      value = value * 10 + static_cast<uint64_t>(text[at] - '0');
      if (value > (uint64_t{1} << 40)) return false;
    }
  }
  size->width = values[0];
  size->height = values[1];
  return true;
}

bool HeaderSize(const ReadAt& read, ImageSize* size) {
  unsigned char head[32] = {};
  size_t n = 0;
  while (n < sizeof head && read(n, 1, head + n)) ++n;
  if (n >= 24 && std::memcmp(head, "\x89PNG\r\n\x1a\n", 8) == 0 &&
      std::memcmp(head + 12, "IHDR", 4) == 0) {
    size->width = Be32(head + 16);
    size->height = Be32(head + 20);
    return true;
  }
  if (n >= 3 && head[0] == 0xff && head[1] == 0xd8 && head[2] == 0xff) return JpegSize(read, size);
  if (n >= 8 && (std::memcmp(head, "II", 2) == 0 || std::memcmp(head, "MM", 2) == 0))
    return TiffSize(read, head, size);
  if (n >= 26 && head[0] == 'B' && head[1] == 'M') {
    const uint32_t header = Le32(head + 14);
    if (header == 12) {  // BITMAPCOREHEADER: 16-bit sizes.
      size->width = Le16(head + 18);
      size->height = Le16(head + 20);
    } else {  // Signed 32-bit; a negative height is a top-down bitmap.
      const auto w = static_cast<int32_t>(Le32(head + 18)),
                 h = static_cast<int32_t>(Le32(head + 22));
      size->width = static_cast<uint64_t>(std::abs(static_cast<int64_t>(w)));
      size->height = static_cast<uint64_t>(std::abs(static_cast<int64_t>(h)));
    }
    return true;
  }
  if (n >= 30 && std::memcmp(head, "RIFF", 4) == 0 && std::memcmp(head + 8, "WEBP", 4) == 0) {
    if (std::memcmp(head + 12, "VP8X", 4) == 0) {  // Canvas size minus one, 24 bits each.
      size->width = (Le32(head + 24) & 0xffffff) + 1;
      size->height = (Le32(head + 27) & 0xffffff) + 1;  // Bytes 27-29 (n >= 30).

      return true;
    }
    if (std::memcmp(head + 12, "VP8L", 4) == 0 && head[20] == 0x2f) {  // 14 bits each, minus one.
      const uint32_t bits = Le32(head + 21);
      size->width = (bits & 0x3fff) + 1;
      size->height = ((bits >> 14) & 0x3fff) + 1;
      return true;
    }
    if (std::memcmp(head + 12, "VP8 ", 4) == 0 && head[23] == 0x9d && head[24] == 0x01 &&
        head[25] == 0x2a) {  // A key frame's 14-bit sizes.
      size->width = Le16(head + 26) & 0x3fff;
      size->height = Le16(head + 28) & 0x3fff;
      return true;
    }
    return false;
  }
  if (n >= 3 && head[0] == 'P' &&
      ((head[1] >= '1' && head[1] <= '7') || head[1] == 'F' || head[1] == 'f'))
    return PnmSize(read, size);
  return false;
}

}  // namespace

bool ImageHeaderSize(const std::string& path, ImageSize* size) {
  // Read whole (as the readers do): the JPEG walk may reach far into it.
  const auto bytes = ReadInputFile(path, "image", std::uintmax_t{512} << 20, nullptr);
  return bytes && ImageBytesSize(*bytes, size);
}

bool ImageBytesSize(const std::string& bytes, ImageSize* size) {
  const ReadAt read = [&](uint64_t offset, size_t n, unsigned char* out) {
    if (offset > bytes.size() || bytes.size() - offset < n) return false;
    std::memcpy(out, bytes.data() + offset, n);
    return true;
  };
  return HeaderSize(read, size);
}

std::string ImageSizeProblem(const ImageSize& size) {
  if (size.width == 0 || size.height == 0) return "its header gives a size of 0";
  if (size.width > INT_MAX || size.height > INT_MAX ||
      static_cast<double>(size.width) * static_cast<double>(size.height) >
          static_cast<double>(kMaxImagePixels)) {
    return std::to_string(size.width) + " x " + std::to_string(size.height) +
           " pixels, over the limit of " + std::to_string(kMaxImagePixels >> 20) + " Mpx";
  }
  return "";
}

std::string LowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace chromatag
