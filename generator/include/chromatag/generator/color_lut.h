// A printer colour correction as a 3D LUT file (.cube and the other formats
// OpenColorIO reads), applied to the palette's sRGB before it is written.
// The calibration tool writes such files.
#ifndef CHROMATAG_GENERATOR_COLOR_LUT_H_
#define CHROMATAG_GENERATOR_COLOR_LUT_H_

#include <memory>
#include <string>

#include "chromatag/families/color.h"

namespace chromatag {

class ColorLut {
 public:
  // Reads `path` through an OpenColorIO FileTransform. Returns nullptr and
  // sets *error for a missing, unreadable or malformed file, and for a LUT
  // that gives outputs that are not numbers or lie far outside 0-1, or that maps
  // every colour to nearly one (size 1, a folding domain).
  static std::unique_ptr<ColorLut> Load(const std::string& path, std::string* error = nullptr);
  ~ColorLut();

  // Maps gamma-encoded sRGB (channels in [0, 1]) to the RGB to send to the
  // printer, clamped to [0, 1].
  Rgb Apply(const Rgb& rgb) const;

  const std::string& path() const { return path_; }

 private:
  struct Impl;
  ColorLut() = default;
  // False with *fault when the LUT is unusable (Load's checks).
  bool Probe(std::string* fault) const;
  std::string path_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace chromatag

#endif  // CHROMATAG_GENERATOR_COLOR_LUT_H_
