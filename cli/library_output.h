// What third-party libraries print. libpng and libjpeg (through OpenCV),
// poppler and FFmpeg write their own lines to the standard error
// descriptor, beside the tool's one message for a bad input. The tool
// writes its own output to a copy of that descriptor (ToolErr) and points
// descriptor 2 at a pipe that a thread drains: the libraries' lines are
// dropped, but the last 4 KiB are kept and shown if the process dies of a
// fatal signal (abort, segmentation fault), so a crash still says why.
// CHROMATAG_LIBRARY_OUTPUT=1 in the environment lets them through as they
// are. In a build with a sanitizer its reports go to the tool's descriptor.
#ifndef CHROMATAG_CLI_LIBRARY_OUTPUT_H_
#define CHROMATAG_CLI_LIBRARY_OUTPUT_H_

#include <cstdio>

namespace chromatag::cli {

// Sets the above up; call once, first thing in main. Does nothing when
// descriptor 2 is closed or a pipe cannot be made.
void CaptureLibraryOutput();

// Where the tool's own messages go: the original standard error.
std::FILE* ToolErr();

}  // namespace chromatag::cli

#endif  // CHROMATAG_CLI_LIBRARY_OUTPUT_H_
