// What the print check's sources share (print_internal.h).
#include "print_internal.h"

#include <cstdarg>
#include <cstdio>

#include "chromatag/base/input_file.h"

namespace chromatag::internal {

std::string Format(const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  return buffer;
}

bool SheetIsSane(const SheetRecord& record, std::string* why) {
  constexpr double kMaxPageMm = 10000.0;
  if (!(record.tag_size_mm > 0 && record.tag_size_mm <= kMaxPageMm)) {
    *why = Format("its tag size %g mm is outside (0, 10000] mm", record.tag_size_mm);
    return false;
  }
  if (!(record.page.width_mm > 0 && record.page.width_mm <= kMaxPageMm &&
        record.page.height_mm > 0 && record.page.height_mm <= kMaxPageMm)) {
    *why = Format("its page %g x %g mm is outside (0, 10000] mm a side", record.page.width_mm,
                  record.page.height_mm);
    return false;
  }
  return true;
}

std::string Utf8OrReplaced(const std::string& text) {
  if (IsValidUtf8(text)) return text;
  std::string out = text;
  for (char& c : out)
    if (static_cast<unsigned char>(c) >= 0x80) c = '?';
  return out;
}

}  // namespace chromatag::internal
