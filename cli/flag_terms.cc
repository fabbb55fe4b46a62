#include "flag_terms.h"

#include <string_view>
#include <utility>

namespace chromatag::cli {
namespace {

// (library phrase, the command line's), each specific enough to match only
// the message it comes from.
constexpr std::pair<std::string_view, std::string_view> kTerms[] = {
    // generate (generator/sheet_request.cc, sheet_layout.cc, sheet_render.cc)
    {"the board must be COLSxROWS", "--board must be COLSxROWS"},
    {"a spacing is for boards (COLSxROWS tags); sheets take a gap",
     "--spacing is for boards (--board COLSxROWS); sheets take --gap"},
    {"say which tags: a list of IDs (0-9,12) or all kept IDs (not both)",
     "say which tags: --ids 0-9,12 or --all (not both)"},
    {"the spacing: ", "--spacing: "},
    {"a spacing of ", "--spacing "},
    {"give a larger spacing or a smaller quiet zone",
     "give a larger --spacing or a smaller --quiet-zone"},
    {"tags wide and high (COLSxROWS, e.g. 6x4)",
     "tags wide and high (--board COLSxROWS, e.g. 6x4)"},
    {"no tag per page, cut ring or crop marks", "no --one-per-page, --cut-ring or --crop-marks"},
    {"the resolution must be in [10, 4800] dpi", "--dpi must be in [10, 4800]"},
    {"; lower the resolution", "; lower --dpi"},
    {"(give no tag size for the largest that fits)",
     "(leave --size out for the largest that fits)"},
    {"or give the format)", "or --format)"},
    // Palettes (families/palette.cc): generate, verify, palettes.
    {", or a palette file)", ", or a palette file with --palette-file)"},
    // verify (verify/sheet_check.cc; print_files.cc and print_verdict.cc for --print)
    {"the resolution must be in [50, 1200] dpi", "--dpi must be in [50, 1200]"},
    {"outside [50, 4800]; give the scanner's resolution",
     "outside [50, 4800]; give the scanner's resolution with --scan-dpi"},
    {"does not record its resolution; give the scanner's resolution",
     "does not record its resolution; give it with --scan-dpi (the scanner's dpi)"},
    {"if the scanner used another resolution, give the scanner's resolution",
     "if the scanner used another resolution, give it with --scan-dpi"},
    {"give the camera's intrinsics, add a photo", "give --camera, add a photo"},
    {"the lens distorts (give the camera's intrinsics)", "the lens distorts (give --camera)"},
    // detect (detector/read_image.cc)
    {"a PDF or SVG sheet is rasterised and checked by the round trip (verify)",
     "a PDF or SVG sheet is checked by chromatag verify"},
    // calibrate (calib/locate_sheet.cc)
    {"or the wrong sheet's sidecar)", "or the wrong --sheet)"},
};

}  // namespace

std::string InFlagTerms(std::string message) {
  for (const auto& [library, flags] : kTerms) {
    for (size_t at = 0; (at = message.find(library, at)) != std::string::npos; at += flags.size())
      message.replace(at, library.size(), flags);
  }
  return message;
}

}  // namespace chromatag::cli
