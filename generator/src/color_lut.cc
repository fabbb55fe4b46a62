#include "chromatag/generator/color_lut.h"

#include "chromatag/base/input_file.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>

namespace OCIO = OCIO_NAMESPACE;

namespace chromatag {

struct ColorLut::Impl {
  OCIO::ConstCPUProcessorRcPtr processor;
};

ColorLut::~ColorLut() = default;

std::unique_ptr<ColorLut> ColorLut::Load(const std::string& path, std::string* error) {
  // OpenColorIO reads the file itself; checked here first, so that a
  // FIFO, a device or a huge file is one clear error.
  constexpr std::uintmax_t kMaxLutBytes = 64u << 20;  // A 65^3 .cube is about 10 MiB.
  if (!ReadInputFile(path, "colour LUT", kMaxLutBytes, error)) return nullptr;
  try {
    OCIO::FileTransformRcPtr transform = OCIO::FileTransform::Create();
    transform->setSrc(path.c_str());
    transform->setInterpolation(OCIO::INTERP_BEST);
    OCIO::ConstProcessorRcPtr processor = OCIO::Config::CreateRaw()->getProcessor(transform);
    std::unique_ptr<ColorLut> lut(new ColorLut());
    lut->path_ = path;
    lut->impl_ = std::make_unique<Impl>();
    lut->impl_->processor = processor->getDefaultCPUProcessor();
    std::string fault;
    if (!lut->Probe(&fault)) {
      if (error) *error = "colour LUT '" + path + "' " + fault;
      return nullptr;
    }
    return lut;
  } catch (const OCIO::Exception& e) {
    if (error) {
      std::string reason = e.what();
      std::replace(reason.begin(), reason.end(), '\n', ' ');
      *error = "colour LUT '" + path + "' is not a LUT OpenColorIO can read (.cube, .3dl, " +
               ".csp, .spi3d, ...): " + reason;
    }
    return nullptr;
  }
}

bool ColorLut::Probe(std::string* fault) const {
  // A 9 x 9 x 9 grid over the input cube: every output a number in -0.25-1.25,
  // and the outputs spread (a LUT of size 1, or a domain that folds every
  // input onto one point, prints every shade alike).
  constexpr int kSteps = 9;
  std::array<float, 3> low = {1e9f, 1e9f, 1e9f}, high = {-1e9f, -1e9f, -1e9f};
  char at[64];
  for (int i = 0; i < kSteps * kSteps * kSteps; ++i) {
    const float in[3] = {static_cast<float>(i % kSteps) / (kSteps - 1),
                         static_cast<float>(i / kSteps % kSteps) / (kSteps - 1),
                         static_cast<float>(i / (kSteps * kSteps)) / (kSteps - 1)};
    float out[3] = {in[0], in[1], in[2]};
    impl_->processor->applyRGB(out);
    std::snprintf(at, sizeof at, "RGB (%.3g, %.3g, %.3g)", in[0], in[1], in[2]);
    for (int c = 0; c < 3; ++c) {
      if (!std::isfinite(out[c])) {
        *fault = std::string("gives a value that is not a number for ") + at;
        return false;
      }
      // Apply clamps to 0-1; a LUT far outside it is not a printer correction.
      if (out[c] < -0.25f || out[c] > 1.25f) {
        char value[32];
        std::snprintf(value, sizeof value, "%.3g", out[c]);
        *fault = std::string("gives ") + value + " for " + at + ", outside 0-1";
        return false;
      }
      low[c] = std::min(low[c], out[c]);
      high[c] = std::max(high[c], out[c]);
    }
  }
  if (high[0] - low[0] < 0.25f && high[1] - low[1] < 0.25f && high[2] - low[2] < 0.25f) {
    *fault =
        "maps every colour to nearly the same one (a LUT of size 1, or a domain that folds the "
        "inputs together): the tags' shades would print alike";
    return false;
  }
  // Each channel must still rise with itself (the others at mid-grey): a
  // printer correction bends the channels, it does not flatten or swap them
  // (OpenColorIO reads "nan" entries as 0, which flattens one).
  static const char* kNames[3] = {"red", "green", "blue"};
  for (int c = 0; c < 3; ++c) {
    float lo[3] = {0.5f, 0.5f, 0.5f}, hi[3] = {0.5f, 0.5f, 0.5f};
    lo[c] = 0.0f;
    hi[c] = 1.0f;
    impl_->processor->applyRGB(lo);
    impl_->processor->applyRGB(hi);
    if (!(hi[c] - lo[c] >= 0.1f)) {
      char value[96];
      std::snprintf(value, sizeof value, "%.3g to %.3g", lo[c], hi[c]);
      *fault = std::string("does not raise ") + kNames[c] + " with " + kNames[c] + " (from " +
               value + " as the input goes from 0 to 1): the tags' shades would print wrong";
      return false;
    }
  }
  return true;
}

Rgb ColorLut::Apply(const Rgb& rgb) const {
  float pixel[3] = {static_cast<float>(rgb.r), static_cast<float>(rgb.g),
                    static_cast<float>(rgb.b)};
  impl_->processor->applyRGB(pixel);
  auto clamp = [](float v) { return std::clamp(static_cast<double>(v), 0.0, 1.0); };
  return {clamp(pixel[0]), clamp(pixel[1]), clamp(pixel[2])};
}

}  // namespace chromatag
