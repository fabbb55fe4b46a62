// Helpers shared by the cross-library tests.
#ifndef CHROMATAG_TESTS_TEST_UTIL_H_
#define CHROMATAG_TESTS_TEST_UTIL_H_

#include <string>
#include <vector>

namespace chromatag::testing {

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs `program` with `args` (each passed as one argument, no shell
// interpretation) and collects its exit code, standard output and error.
CommandResult RunCommand(const std::string& program, const std::vector<std::string>& args);

// Runs the chromatag executable built with the tests (CHROMATAG_CLI_PATH).
CommandResult RunChromatag(const std::vector<std::string>& args);

// The whole contents of a file; empty if it cannot be read.
std::string ReadFile(const std::string& path);

// Number of lines in `text` (a last line without a newline counts).
int CountLines(const std::string& text);

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_TEST_UTIL_H_
