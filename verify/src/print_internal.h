// What the print check's sources (print_check.cc, print_files.cc,
// print_report.cc) share.
#ifndef CHROMATAG_VERIFY_SRC_PRINT_INTERNAL_H_
#define CHROMATAG_VERIFY_SRC_PRINT_INTERNAL_H_

#include <string>

#include "chromatag/generator/sidecar.h"

namespace chromatag::internal {

// printf into a string (512 bytes at most).
std::string Format(const char* format, ...) __attribute__((format(printf, 1, 2)));

// Whether the sidecar's tag size and page are ones a check can work with:
// each in (0, 10 m]. Otherwise *why says which is not.
bool SheetIsSane(const SheetRecord& record, std::string* why);

// `text` with every byte of an invalid UTF-8 sequence replaced by '?', for
// Cairo (whose text calls fail on invalid UTF-8).
std::string Utf8OrReplaced(const std::string& text);

}  // namespace chromatag::internal

#endif  // CHROMATAG_VERIFY_SRC_PRINT_INTERNAL_H_
