#include "chromatag/generator/color_lut.h"

#include "chromatag/families/input_file.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
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

Rgb ColorLut::Apply(const Rgb& rgb) const {
  float pixel[3] = {static_cast<float>(rgb.r), static_cast<float>(rgb.g),
                    static_cast<float>(rgb.b)};
  impl_->processor->applyRGB(pixel);
  auto clamp = [](float v) { return std::clamp(static_cast<double>(v), 0.0, 1.0); };
  return {clamp(pixel[0]), clamp(pixel[1]), clamp(pixel[2])};
}

}  // namespace chromatag
