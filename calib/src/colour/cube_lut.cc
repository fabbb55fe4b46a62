// Baking the printer correction into a .cube LUT (cube_lut.h).
#include "chromatag/calib/cube_lut.h"

#include <OpenColorIO/OpenColorIO.h>

#include <algorithm>
#include <sstream>

namespace OCIO = OCIO_NAMESPACE;

namespace chromatag {

std::optional<std::string> BakeCubeLut(const std::vector<PrinterModel>& models, int size,
                                       std::string* error) {
  if (size < 2 || size > 65) {
    if (error) *error = "LUT size must be in [2, 65], got " + std::to_string(size);
    return std::nullopt;
  }
  if (models.empty()) {
    if (error) *error = "no printer model to invert";
    return std::nullopt;
  }
  try {
    OCIO::Lut3DTransformRcPtr lut = OCIO::Lut3DTransform::Create(size);
    for (int r = 0; r < size; ++r) {
      for (int g = 0; g < size; ++g) {
        for (int b = 0; b < size; ++b) {
          const Rgb intended{static_cast<double>(r) / (size - 1),
                             static_cast<double>(g) / (size - 1),
                             static_cast<double>(b) / (size - 1)};
          const Rgb send = InvertPrinter(models, SrgbToLab(intended), intended);
          lut->setValue(r, g, b, static_cast<float>(send.r), static_cast<float>(send.g),
                        static_cast<float>(send.b));
        }
      }
    }
    // Two colour spaces: "intended" (the reference: the file's sRGB) and
    // "printer", reached from it through the LUT. Not the raw config: its
    // one space is marked as data, and OpenColorIO leaves data unchanged.
    OCIO::ConfigRcPtr config = OCIO::Config::Create();
    OCIO::ColorSpaceRcPtr intended = OCIO::ColorSpace::Create();
    intended->setName("intended");
    config->addColorSpace(intended);
    OCIO::ColorSpaceRcPtr printer = OCIO::ColorSpace::Create();
    printer->setName("printer");
    printer->setTransform(lut, OCIO::COLORSPACE_DIR_FROM_REFERENCE);
    config->addColorSpace(printer);
    config->setRole(OCIO::ROLE_DEFAULT, "intended");
    OCIO::BakerRcPtr baker = OCIO::Baker::Create();
    baker->setConfig(config);
    baker->setFormat("resolve_cube");
    baker->setInputSpace("intended");
    baker->setTargetSpace("printer");
    baker->setCubeSize(size);
    baker->getFormatMetadata().addChildElement(
        OCIO::METADATA_DESCRIPTION, "ChromaTag printer correction from chromatag calibrate");
    std::ostringstream out;
    baker->bake(out);
    return out.str();
  } catch (const OCIO::Exception& e) {
    if (error) *error = std::string("OpenColorIO could not bake the LUT: ") + e.what();
    return std::nullopt;
  }
}

}  // namespace chromatag
