// Writing outputs without ever leaving a half-written file: everything goes to
// a temporary file beside the target and is renamed into place at the end.
#ifndef CHROMATAG_GENERATOR_FILE_UTIL_H_
#define CHROMATAG_GENERATOR_FILE_UTIL_H_

#include <string>
#include <vector>

namespace chromatag {

struct OutputFile {
  std::string path;
  std::string contents;
};

// Writes every file to "<path>.tmp-<pid>" and then renames them all into
// place. If any write fails, removes the temporaries, leaves every existing
// target untouched, and returns false with *error naming the path.
bool WriteFilesAtomically(const std::vector<OutputFile>& files, std::string* error = nullptr);

// SHA-256 of `data`, as 64 lower-case hex digits (FIPS 180-4).
std::string Sha256Hex(const std::string& data);

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_FILE_UTIL_H_
