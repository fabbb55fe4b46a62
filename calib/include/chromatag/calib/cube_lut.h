// The printer correction as a 3D LUT (.cube), baked through OpenColorIO, for
// `chromatag generate --color-lut` (generator/color_lut.h reads it).
#ifndef CHROMATAG_CALIB_CUBE_LUT_H_
#define CHROMATAG_CALIB_CUBE_LUT_H_

#include <optional>
#include <string>
#include <vector>

#include "chromatag/calib/printer_model.h"

namespace chromatag {

// Samples, on a size^3 grid of gamma-encoded sRGB (the intended colours),
// the RGB to send to the printer so that the print, as `models` predict it,
// shows that colour relative to the paper white; colours the printer cannot
// reach map to the nearest it can (least squares in CIELAB over all models).
// Then bakes the grid into .cube text with OpenColorIO's Baker
// ("resolve_cube"). size in [2, 65]; 17 is the usual printer-profile grid.
// Refuses (nullopt, *error) a size out of range, no models, or an
// OpenColorIO failure.
std::optional<std::string> BakeCubeLut(const std::vector<PrinterModel>& models, int size,
                                       std::string* error = nullptr);

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_CUBE_LUT_H_
