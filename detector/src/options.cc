#include "chromatag/detector/options.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "chromatag/families/family.h"

namespace chromatag {

const char* LensModelName(LensModel model) {
  return model == LensModel::kFisheye ? "fisheye" : "pinhole";
}

bool IntrinsicsFromMatrix(const double (&k)[9], CameraIntrinsics* camera, std::string* error) {
  auto fail = [&](int i, const std::string& why) {
    if (error) {
      char value[32];
      std::snprintf(value, sizeof(value), "%g", k[i]);
      *error = "camera matrix entry [" + std::to_string(i / 3) + "][" + std::to_string(i % 3) +
               "] is " + value + ", " + why +
               " (the matrix must be [fx 0 cx; 0 fy cy; 0 0 1], row by row)";
    }
    return false;
  };
  for (int i = 0; i < 9; ++i) {
    if (!std::isfinite(k[i])) return fail(i, "not a finite number");
  }
  const double tolerance = 1e-9 * std::max(1.0, std::abs(k[0]));
  if (std::abs(k[6]) > tolerance || std::abs(k[7]) > tolerance)
    return fail(std::abs(k[6]) > tolerance ? 6 : 7,
                "not 0: is the matrix transposed, as MATLAB writes it?");
  if (std::abs(k[3]) > tolerance) return fail(3, "not 0");
  if (std::abs(k[1]) > tolerance) return fail(1, "a skew, which is not supported: it must be 0");
  if (std::abs(k[8] - 1.0) > 1e-9) return fail(8, "not 1");
  camera->fx = k[0];
  camera->fy = k[4];
  camera->cx = k[2];
  camera->cy = k[5];
  return true;
}

bool CameraIntrinsics::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(fx > 0.0 && fy > 0.0 && std::isfinite(fx) && std::isfinite(fy)))
    return fail("camera: fx and fy must be finite and > 0 (pixels)");
  if (!std::isfinite(cx) || !std::isfinite(cy)) return fail("camera: cx and cy must be finite");
  const size_t n = distortion.size();
  if (model == LensModel::kFisheye && n != 4)
    return fail("camera: the fisheye model needs 4 distortion coefficients, got " +
                std::to_string(n));
  if (!(n == 0 || n == 4 || n == 5 || n == 8))
    return fail("camera: distortion needs 0, 4, 5 or 8 coefficients, got " + std::to_string(n));
  for (double k : distortion) {
    if (!std::isfinite(k)) return fail("camera: distortion coefficients must be finite");
  }
  return true;
}

namespace {

bool WhiteBalanceIsValid(const std::array<double, 3>& gains, std::string* error) {
  auto fail = [&](const char* format, double a = 0, double b = 0, double c = 0) {
    if (error) {
      char why[160], text[320];
      std::snprintf(why, sizeof(why), format, a, b, c);
      std::snprintf(text, sizeof(text),
                    "white_balance [%g, %g, %g]: %s (gains for R, G, B on linear light, each in "
                    "[%g, 1], the largest 1; [1, 1, 1] for none)",
                    gains[0], gains[1], gains[2], why, kMinWhiteBalanceGain);
      *error = text;
    }
    return false;
  };
  for (double gain : gains) {
    if (!(gain > 0.0 && std::isfinite(gain))) return fail("gains must be finite and positive");
  }
  const double largest = *std::max_element(gains.begin(), gains.end());
  if (largest != 1.0) {
    return fail("the largest gain must be 1; divide all three by it: [%.3g, %.3g, %.3g]",
                gains[0] / largest, gains[1] / largest, gains[2] / largest);
  }
  for (double gain : gains) {
    if (gain < kMinWhiteBalanceGain) return fail("a gain below %g", kMinWhiteBalanceGain);
  }
  return true;
}

}  // namespace

bool DetectorOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (families.empty()) return fail("families: at least one family is needed (16h5, 36h11)");
  for (const auto& name : families) {
    if (!TagFamily::Load(name))
      return fail("families: unknown family '" + name + "' (16h5, 36h11)");
  }
  if (step < 1 || step > 64)
    return fail("step (N) must be in [1, 64], got " + std::to_string(step));
  if (row_step < 0 || row_step > 64) {
    return fail("row_step must be 0 (the same as step) or in [1, 64], got " +
                std::to_string(row_step));
  }
  if (!(adiff_thresh > 0.0 && adiff_thresh <= 200.0)) {
    return fail("adiff_thresh (ADiffThresh) must be in (0, 200]");
  }
  if (!(border_thresh > 0.0 && border_thresh <= 100.0)) {
    return fail("border_thresh (BorderThresh) must be in (0, 100]");
  }
  if (border_run < 1 || border_run > 16) return fail("border_run (M) must be in [1, 16]");
  if (!(max_green_a >= -kMaxGreenALimit && max_green_a <= kMaxGreenALimit))
    return fail("max_green_a must be in [-100, 100] (a* units)");
  if (!(conv_thresh > 0.0 && conv_thresh < 1.0))
    return fail("conv_thresh (ConvThresh) must be in (0, 1)");
  if (max_hamming < -1) return fail("max_hamming must be -1 (family default) or at least 0");
  // The same limit Detector::Create (CodeDecoder) holds it to, so that options
  // that pass here are never refused there.
  for (const auto& name : families) {
    const auto family = TagFamily::Load(name);
    if (max_hamming > family->max_safe_radius()) {
      return fail("max_hamming " + std::to_string(max_hamming) + " is unsafe for " +
                  family->name() + ": at most " + std::to_string(family->max_safe_radius()) +
                  " (-1: the family's default)");
    }
  }
  if (!(min_decision_margin >= 0.0) || !std::isfinite(min_decision_margin)) {
    return fail("min_decision_margin must be a finite number >= 0");
  }
  if (!WhiteBalanceIsValid(white_balance, error)) return false;
  if (camera && !camera->IsValid(error)) return false;
  if (!(tag_size >= 0.0) || !std::isfinite(tag_size))
    return fail("tag_size must be a finite length in metres >= 0 (0: no pose)");
  return true;
}

}  // namespace chromatag
