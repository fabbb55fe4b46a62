#include "icc_press.h"

#include <lcms2.h>

#include <fstream>

namespace chromatag::testing {
namespace {

// LittleCMS reports through a per-context handler; the first message is kept
// so that Load can say why a profile was refused.
void KeepFirstError(cmsContext context, cmsUInt32Number /*code*/, const char* text) {
  auto* message = static_cast<std::string*>(cmsGetContextUserData(context));
  if (message != nullptr && message->empty()) *message = text;
}

}  // namespace

struct IccPress::Transforms {
  std::string lcms_error;  // Written by KeepFirstError; must outlive the context.
  cmsContext context = nullptr;
  cmsHPROFILE srgb = nullptr;
  cmsHPROFILE cmyk = nullptr;
  cmsHPROFILE lab = nullptr;
  cmsHTRANSFORM srgb_to_cmyk = nullptr;
  cmsHTRANSFORM cmyk_to_lab = nullptr;

  ~Transforms() {
    if (cmyk_to_lab != nullptr) cmsDeleteTransform(cmyk_to_lab);
    if (srgb_to_cmyk != nullptr) cmsDeleteTransform(srgb_to_cmyk);
    if (lab != nullptr) cmsCloseProfile(lab);
    if (cmyk != nullptr) cmsCloseProfile(cmyk);
    if (srgb != nullptr) cmsCloseProfile(srgb);
    if (context != nullptr) cmsDeleteContext(context);
  }
};

std::string IccPress::DefaultCmykProfilePath() {
  return "/usr/share/color/icc/ghostscript/default_cmyk.icc";
}

IccPress::~IccPress() = default;

std::unique_ptr<IccPress> IccPress::Load(const std::string& path, std::string* error) {
  auto fail = [&](const std::string& message) -> std::unique_ptr<IccPress> {
    if (error != nullptr) *error = message;
    return nullptr;
  };
  if (!std::ifstream(path, std::ios::binary).good()) {
    return fail("cannot read the ICC profile " + path +
                " (Ghostscript's default_cmyk.icc is in Debian's libgs-common)");
  }
  auto t = std::make_unique<Transforms>();
  t->context = cmsCreateContext(nullptr, &t->lcms_error);
  cmsSetLogErrorHandlerTHR(t->context, KeepFirstError);
  t->cmyk = cmsOpenProfileFromFileTHR(t->context, path.c_str(), "r");
  if (t->cmyk == nullptr) {
    return fail("not an ICC profile: " + path +
                (t->lcms_error.empty() ? "" : " (LittleCMS: " + t->lcms_error + ")"));
  }
  if (cmsGetColorSpace(t->cmyk) != cmsSigCmykData ||
      cmsGetDeviceClass(t->cmyk) != cmsSigOutputClass ||
      !cmsIsIntentSupported(t->cmyk, INTENT_RELATIVE_COLORIMETRIC, LCMS_USED_AS_OUTPUT) ||
      !cmsIsIntentSupported(t->cmyk, INTENT_RELATIVE_COLORIMETRIC, LCMS_USED_AS_INPUT)) {
    return fail(path + " is not a CMYK output (printer) profile; a press needs one, such as " +
                DefaultCmykProfilePath());
  }
  t->srgb = cmsCreate_sRGBProfileTHR(t->context);
  // D50 Lab (nullptr white): the ICC connection space's own white, so a
  // relative colorimetric transform puts the paper at L* 100, a* = b* = 0.
  t->lab = cmsCreateLab4ProfileTHR(t->context, nullptr);
  // Relative colorimetric, 8-bit CMYK, as a print driver sends RGB to a
  // press. No black point compensation (LittleCMS's default; ICC relative
  // colorimetric as defined): with it the mid-tones print lighter and paler
  // too (default's green-0 at b* 33 instead of 31, iccv17's b* gaps 7.1 and
  // 10.7 instead of 7.8 and 11.4); without it the press gives the figures
  // of docs/calibration.md.
  t->srgb_to_cmyk = cmsCreateTransformTHR(t->context, t->srgb, TYPE_RGB_8, t->cmyk, TYPE_CMYK_8,
                                          INTENT_RELATIVE_COLORIMETRIC, 0);
  // What the press puts on paper, relative to the paper (no compensation: the
  // ink's black is what it is).
  t->cmyk_to_lab = cmsCreateTransformTHR(t->context, t->cmyk, TYPE_CMYK_8, t->lab, TYPE_Lab_DBL,
                                         INTENT_RELATIVE_COLORIMETRIC, 0);
  if (t->srgb == nullptr || t->lab == nullptr || t->srgb_to_cmyk == nullptr ||
      t->cmyk_to_lab == nullptr) {
    return fail("LittleCMS cannot build sRGB -> CMYK -> Lab transforms through " + path +
                (t->lcms_error.empty() ? "" : ": " + t->lcms_error));
  }
  std::unique_ptr<IccPress> press(new IccPress());
  press->transforms_ = std::move(t);
  return press;
}

Lab IccPress::Print(const Rgb8& sent) const {
  const uint32_t key = (sent.r << 16) | (sent.g << 8) | sent.b;
  std::lock_guard<std::mutex> lock(mutex_);
  if (auto it = cache_.find(key); it != cache_.end()) return it->second;
  const uint8_t rgb[3] = {sent.r, sent.g, sent.b};
  uint8_t cmyk[4];
  cmsDoTransform(transforms_->srgb_to_cmyk, rgb, cmyk, 1);
  cmsCIELab lab_d50;
  cmsDoTransform(transforms_->cmyk_to_lab, cmyk, &lab_d50, 1);
  // D50 (the ICC connection space) to the project's D65 CIELAB: Bradford
  // chromatic adaptation in XYZ (what cmsAdaptToIlluminant does), so the paper
  // stays white.
  cmsCIEXYZ xyz_d50, xyz_d65;
  cmsLab2XYZ(cmsD50_XYZ(), &xyz_d50, &lab_d50);
  const cmsCIEXYZ d65{kD65White.X, kD65White.Y, kD65White.Z};
  cmsAdaptToIlluminant(&xyz_d65, cmsD50_XYZ(), &d65, &xyz_d50);
  const Lab lab = XyzToLab(Xyz{xyz_d65.X, xyz_d65.Y, xyz_d65.Z});
  cache_.emplace(key, lab);
  return lab;
}

PrintFn IccPress::AsPrintFn() const {
  return [this](const Rgb8& sent) { return Print(sent); };
}

std::vector<NamedCamera> TungstenAndDaylight() {
  SimCamera tungsten;
  tungsten.gains = {1.25, 1.0, 0.7};
  tungsten.exposure = 0.8;
  tungsten.falloff = 0.25;
  tungsten.seed = 11;
  tungsten.page_corners_px = {{{410, 40}, {1190, 70}, {1225, 1160}, {375, 1135}}};
  SimCamera daylight;
  daylight.gains = {0.95, 1.0, 1.08};
  daylight.exposure = 0.9;
  daylight.falloff = 0.15;
  daylight.seed = 12;
  daylight.page_corners_px = {{{430, 60}, {1215, 45}, {1240, 1150}, {400, 1170}}};
  return {{"tungsten", tungsten}, {"daylight", daylight}};
}

}  // namespace chromatag::testing
