// The toolkit's file parsers on arbitrary text. One source, built once per
// parser (CHROMATAG_FUZZ_TARGET chooses which): palette, sheet sidecar,
// calibration sidecar, detector config, camera file, .cube LUT, the
// resolution recorded in an image file's header (verify --print --scan), the
// size an image file's header claims (the image budget's gate), and a board
// bundle YAML (apriltag_ros's tag_bundles).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>

#include "chromatag/base/input_file.h"
#include "chromatag/detector/config.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/color_lut.h"
#include "chromatag/layout/calib_sheet_layout.h"
#include "chromatag/layout/sheet_record.h"
#include "chromatag/rig/board_file.h"
#include "chromatag/rig/camera_file.h"
#include "chromatag/verify/print_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::string error;
#if CHROMATAG_FUZZ_TARGET == 1
  chromatag::ParsePalette(text, "fuzz", &error);
#elif CHROMATAG_FUZZ_TARGET == 2
  chromatag::ParseSidecar(text, "/nonexistent/", &error);
#elif CHROMATAG_FUZZ_TARGET == 3
  chromatag::ParseCalibSidecar(text, &error);
#elif CHROMATAG_FUZZ_TARGET == 4
  chromatag::DetectorOptions options;
  chromatag::ParseDetectorConfig(text, &options, &error);
#elif CHROMATAG_FUZZ_TARGET == 5
  // The first byte picks the layout, as the extension does.
  if (text.empty()) return 0;
  static const char* kExtensions[] = {".yaml", ".json", ".xml"};
  chromatag::CameraIntrinsics camera;
  chromatag::ParseCameraFile(text.substr(1), kExtensions[data[0] % 3], &camera, &error);
#elif CHROMATAG_FUZZ_TARGET == 6
  // OpenColorIO reads LUTs from files only.
  static const std::string path = "/tmp/chromatag-fuzz-" + std::to_string(getpid()) + ".cube";
  std::ofstream(path, std::ios::binary) << text;
  auto lut = chromatag::ColorLut::Load(path, &error);
  if (lut) lut->Apply({0.5, 0.2, 0.9});
  std::remove(path.c_str());  // Nothing left in /tmp when the run ends.
#elif CHROMATAG_FUZZ_TARGET == 7
  chromatag::ReadImageDpi(text);
#elif CHROMATAG_FUZZ_TARGET == 8
  chromatag::ImageSize image_size;
  if (chromatag::ImageBytesSize(text, &image_size)) chromatag::ImageSizeProblem(image_size);
#elif CHROMATAG_FUZZ_TARGET == 9
  chromatag::ParseBundleYaml(text, "", &error);
#endif
  return 0;
}
