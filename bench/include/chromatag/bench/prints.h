// The camera set's printers (PrintKind), and the detector config the colour
// calibration derives for each: the calibration sheet in the print's
// palette, printed the same way, photographed and measured as `chromatag
// calibrate` does.
#ifndef CHROMATAG_BENCH_PRINTS_H_
#define CHROMATAG_BENCH_PRINTS_H_

#include <functional>
#include <optional>
#include <string>

#include "chromatag/bench/dataset.h"
#include "chromatag/detector/options.h"
#include "chromatag/families/color.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag::bench {

// A printer: the printed colour (CIELAB relative to the paper white) of a
// sent 8-bit sRGB colour; the same type as the tests' PrintFn (calib_sim.h), so
// their page renderers take it.
using Printer = std::function<Lab(const Rgb8&)>;

// The printer of `kind`. Exact prints keep the file's colours, with ink's
// black no darker than L* 14 (spec section 6 measured 14 on the authors'
// prints) and the paper no whiter than L* 95; the faded one scales a* and b*
// by kFadedChroma as well; the press is LittleCMS through Ghostscript's SWOP
// profile. Empty and *error when the press profile cannot be loaded.
Printer MakePrinter(PrintKind kind, std::string* error = nullptr);

// The tag colours of `kind` as printed: each of its palette's shades sent
// as 8-bit sRGB through `printer`, then back to sRGB for rendering.
TagColors PrintedTagColors(PrintKind kind, const Printer& printer);

// What `chromatag calibrate` derives for tags printed as `kind`: the
// calibration sheet in the print's palette (calib-sheet --palette), printed
// by MakePrinter(kind) and photographed under a tungsten lamp and daylight
// (the tests' TungstenAndDaylight), measured and turned into detector
// options. nullopt and *error when a step fails.
std::optional<DetectorOptions> CalibratedOptions(PrintKind kind, std::string* error = nullptr);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_PRINTS_H_
