// The libraries' messages name what is wrong in their own terms ("the board
// must be COLSxROWS ..."), as the Python module's users read them too; the
// command line names the flag that sets it ("--board must be COLSxROWS
// ..."). This is the one table from the first to the second.
#ifndef CHROMATAG_CLI_FLAG_TERMS_H_
#define CHROMATAG_CLI_FLAG_TERMS_H_

#include <string>

namespace chromatag::cli {

// `message` with each library phrase of the table replaced by the flags
// that set it. Fail applies it to every error line; call it for messages
// printed another way (a skipped input, a verdict's problems).
std::string InFlagTerms(std::string message);

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_FLAG_TERMS_H_
