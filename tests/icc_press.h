// A real printer for the tests: pages printed through an ICC output profile
// with LittleCMS. The default is Ghostscript's default_cmyk.icc (a CMYK SWOP
// press, Debian's libgs-common): sRGB -> the press's CMYK (relative
// colorimetric, as a print driver sends it) -> the CIELAB the press puts on
// paper, relative to the paper white. Unlike SimPrinter it is not the kind
// of model the calibration tool fits, so it can show what a real press does
// that the model does not.
#ifndef CHROMATAG_TESTS_ICC_PRESS_H_
#define CHROMATAG_TESTS_ICC_PRESS_H_

#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "calib_sim.h"
#include "chromatag/families/color.h"

namespace chromatag::testing {

class IccPress {
 public:
  // Where libgs-common puts Ghostscript's SWOP profile.
  static std::string DefaultCmykProfilePath();

  // Loads a CMYK output profile. nullptr and *error when it is missing or
  // not a CMYK output profile.
  static std::unique_ptr<IccPress> Load(const std::string& path = DefaultCmykProfilePath(),
                                        std::string* error = nullptr);
  ~IccPress();

  // The printed colour of `sent`, CIELAB relative to the paper white (D50
  // adapted to the D65 white the rest of the project uses).
  Lab Print(const Rgb8& sent) const;

  // The same as a PrintFn for calib_sim's page renderers.
  PrintFn AsPrintFn() const;

 private:
  IccPress() = default;
  struct Transforms;
  std::unique_ptr<Transforms> transforms_;
  mutable std::mutex mutex_;
  mutable std::unordered_map<uint32_t, Lab> cache_;
};

// The two lights of the calibration through the press (the test and
// docs/calibration.md): a tungsten lamp, warm as an uncorrected camera sees
// it (R 1.25, B 0.7), and daylight by a window, slightly cool; each with the
// portrait A4 page filling most of a 1600 x 1200 frame in mild perspective
// (about 3.9 px/mm, 75 px a 20 mm tag).
struct NamedCamera {
  std::string name;
  SimCamera camera;
};
std::vector<NamedCamera> TungstenAndDaylight();

}  // namespace chromatag::testing

#endif  // CHROMATAG_TESTS_ICC_PRESS_H_
