#include "chromatag/bench/dataset.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "chromatag/bench/prints.h"
#include "chromatag/families/color.h"
#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/tag_renderer.h"
#include "dataset_impl.h"

namespace chromatag::bench {
namespace {

// Natural colour photographs from Debian's opencv-doc; synthetic images,
// logos, text and the grey calibration chessboards are left out.
const char* const kPhotoNames[] = {
    "aero1.jpg",        "aero3.jpg",
    "aloeL.jpg",        "apple.jpg",
    "baboon.jpg",       "board.jpg",
    "building.jpg",     "butterfly.jpg",
    "ela_original.jpg", "fruits.jpg",
    "home.jpg",         "leuvenA.jpg",
    "leuvenB.jpg",      "licenseplate_motion.jpg",
    "messi5.jpg",       "orange.jpg",
    "pca_test1.jpg",    "squirrel_cls.jpg",
    "starry_night.jpg", "stuff.jpg",
    "graf1.png",        "graf3.png",
    "rubberwhale1.png", "rubberwhale2.png",
    "smarties.png",     "box_in_scene.png",
    "basketball1.png",  "HappyFish.jpg",
};

// The classic card: 16h5 (6-cell black square), 2-cell quiet zones: 20 x 10
// cells, so in tag units (black-square sides) it spans [-5/3, 5/3] x
// [-5/6, 5/6].
const SheetLayout kClassicLayout{6, 2};
constexpr int kTagCells = 10;  // One tag with its quiet zones.
// Texture resolutions, pixels per cell; each frame picks the smallest one not
// coarser than its supersampled image (the largest is magnified a little).
constexpr int kTextureLevels[] = {2, 4, 8, 16, 32};
constexpr int kNumLevels = sizeof(kTextureLevels) / sizeof(kTextureLevels[0]);

// Ink chroma as a share of the file's (PrintedColors), the same for every
// classic frame.
constexpr double kPrintChroma = 0.85;

// Tungsten-like uncorrected cast (linear R, G, B gains) for NWB frames.
const cv::Vec3d kCastGains(1.0, 0.74, 0.42);

// libapriltag's picture padded to the classic 2-cell quiet zone.
cv::Mat AprilTagCells(apriltag_family_t* family, int id) {
  const cv::Mat picture = AprilTagPicture(family, id);
  cv::Mat cells(kTagCells, kTagCells, CV_8UC1, cv::Scalar(1));
  const int pad = (kTagCells - picture.cols) / 2;
  picture.copyTo(cells(cv::Rect(pad, pad, picture.cols, picture.rows)));
  return cells;
}

cv::Mat ToLinearPremultiplied(const cv::Mat& rgb8) {
  cv::Mat out(rgb8.size(), CV_32FC4);
  for (int y = 0; y < rgb8.rows; ++y) {
    for (int x = 0; x < rgb8.cols; ++x) {
      const cv::Vec3b p = rgb8.at<cv::Vec3b>(y, x);
      out.at<cv::Vec4f>(y, x) = {SrgbToLinearF(p[2] / 255.0f), SrgbToLinearF(p[1] / 255.0f),
                                 SrgbToLinearF(p[0] / 255.0f), 1.0f};
    }
  }
  return out;
}

// The whole sheet at `ppc` pixels per cell, as 8-bit RGB.
cv::Mat SheetRgb(const TagFamily& family, int id, const TagColors& colors, apriltag_family_t* april,
                 int ppc) {
  TagDrawOptions draw;
  draw.quiet_zone_cells = kClassicLayout.quiet_cells;
  const RgbImage chroma = RasterizeTag(family, id, colors, ppc, draw);
  assert(chroma.width == kTagCells * ppc && chroma.height == kTagCells * ppc);
  cv::Mat sheet(kClassicLayout.sheet_cells_y() * ppc, kClassicLayout.sheet_cells_x() * ppc,
                CV_8UC3);
  cv::Mat(chroma.height, chroma.width, CV_8UC3, const_cast<uint8_t*>(chroma.pixels.data()))
      .copyTo(sheet(cv::Rect(0, 0, chroma.width, chroma.height)));
  const cv::Mat cells = AprilTagCells(april, id);
  const Rgb8 black = ToRgb8(colors[Shade::kBlack]), white = ToRgb8(colors[Shade::kWhite]);
  for (int y = 0; y < kTagCells * ppc; ++y) {
    for (int x = 0; x < kTagCells * ppc; ++x) {
      const Rgb8& c = cells.at<uint8_t>(y / ppc, x / ppc) ? white : black;
      sheet.at<cv::Vec3b>(y, kTagCells * ppc + x) = {c.r, c.g, c.b};
    }
  }
  return sheet;
}

}  // namespace

const char* ConditionName(ColorCondition condition) {
  return condition == ColorCondition::kWhiteBalanced ? "WB" : "NWB";
}

const char* DatasetKindName(DatasetKind kind) {
  return kind == DatasetKind::kCamera ? "camera" : "classic";
}

std::optional<DatasetKind> ParseDatasetKind(const std::string& name) {
  if (name == "classic") return DatasetKind::kClassic;
  if (name == "camera") return DatasetKind::kCamera;
  return std::nullopt;
}

std::vector<std::string> DatasetFamilies(DatasetKind kind) {
  if (kind == DatasetKind::kCamera) return {"16h5", "36h11"};
  return {"16h5"};
}

const char* PrintKindName(PrintKind kind) {
  switch (kind) {
    case PrintKind::kDefault:
      return "default";
    case PrintKind::kDefaultPress:
      return "default-press";
    case PrintKind::kIccv17:
      return "iccv17";
    case PrintKind::kIccv17Faded:
      return "iccv17-faded";
  }
  return "?";
}

const char* PrintKindPalette(PrintKind kind) {
  return kind == PrintKind::kDefault || kind == PrintKind::kDefaultPress ? "default" : "iccv17";
}

const char* BayerModeName(BayerMode mode) {
  switch (mode) {
    case BayerMode::kNone:
      return "none";
    case BayerMode::kBilinear:
      return "bilinear";
    case BayerMode::kEdgeAware:
      return "edge-aware";
  }
  return "?";
}

DatasetOptions DatasetOptions::ForKind(DatasetKind kind) {
  DatasetOptions options;
  options.kind = kind;
  if (kind == DatasetKind::kCamera) {
    options.tag_free_share = 0.25;
    options.min_size_px = 12.0;
    options.max_size_px = 250.0;
  }
  return options;
}

bool DatasetOptions::IsValid(std::string* error) const {
  std::ostringstream why;
  if (kind != DatasetKind::kClassic && kind != DatasetKind::kCamera) {
    why << "kind is classic or camera; ";
  }
  if (width < 64 || height < 64) why << "frames must be at least 64x64 pixels; ";
  if (num_frames < 1) why << "num_frames must be at least 1; ";
  if (!(tag_free_share >= 0.0 && tag_free_share <= 1.0)) why << "tag_free_share is in [0, 1]; ";
  if (!(min_size_px >= 4.0 && max_size_px >= min_size_px)) {
    why << "sizes need 4 <= min_size_px <= max_size_px; ";
  }
  if (!(max_view_angle_deg >= 0.0 && max_view_angle_deg <= 80.0)) {
    why << "max_view_angle_deg is in [0, 80]; ";
  }
  if (!(focal_px > 0.0)) why << "focal_px must be positive; ";
  if (supersampling < 1 || supersampling > 8) why << "supersampling is in [1, 8]; ";
  const std::string text = why.str();
  if (error) *error = text.empty() ? "" : text.substr(0, text.size() - 2);
  return text.empty();
}

double QuadSizePx(const std::array<cv::Point2d, 4>& quad) {
  double twice_area = 0.0;
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d& a = quad[i];
    const cv::Point2d& b = quad[(i + 1) % 4];
    twice_area += a.x * b.y - b.x * a.y;
  }
  return std::sqrt(std::abs(twice_area) / 2.0);
}

Dataset::Dataset(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Dataset::~Dataset() = default;
const DatasetOptions& Dataset::options() const { return impl_->options; }
const std::vector<std::string>& Dataset::photos() const { return impl_->photo_names; }

std::unique_ptr<Dataset> Dataset::Create(const DatasetOptions& options, std::string* error) {
  if (!options.IsValid(error)) return nullptr;
  auto impl = std::make_unique<Impl>();
  impl->options = options;
  impl->family = TagFamily::Load("16h5", error);
  if (!impl->family) return nullptr;
  const auto palette = BuiltinPalette(options.palette, error);
  if (!palette) return nullptr;
  for (const char* name : kPhotoNames) {
    const std::filesystem::path path = std::filesystem::path(options.photo_dir) / name;
    cv::Mat photo = cv::imread(path.string(), cv::IMREAD_COLOR);
    if (photo.empty()) continue;
    impl->photo_names.push_back(name);
    impl->photos.push_back(photo);
  }
  if (impl->photos.size() < 4) {
    if (error) {
      *error = "found " + std::to_string(impl->photos.size()) + " background photographs in " +
               options.photo_dir + "; need at least 4 (install opencv-doc)";
    }
    return nullptr;
  }
  impl->srgb_to_linear.resize(256);
  for (int i = 0; i < 256; ++i) impl->srgb_to_linear[i] = SrgbToLinearF(i / 255.0f);
  impl->linear_to_srgb.resize(4096);
  for (int i = 0; i < 4096; ++i) {
    const double encoded = LinearToSrgb(i / 4095.0);
    impl->linear_to_srgb[i] =
        static_cast<uint8_t>(std::lround(std::clamp(encoded, 0.0, 1.0) * 255));
  }
  if (options.kind == DatasetKind::kCamera) {
    if (!impl->LoadCameraFamilies(error)) return nullptr;
    for (int k = 0; k < kNumPrintKinds; ++k) {
      const PrintKind kind = static_cast<PrintKind>(k);
      const Printer printer = MakePrinter(kind, error);
      if (!printer) return nullptr;
      impl->printed_colors[k] = PrintedTagColors(kind, printer);
    }
    return std::unique_ptr<Dataset>(new Dataset(std::move(impl)));
  }
  const TagColors colors = PrintedColors(*palette, kPrintChroma);
  apriltag_family_t* april = tag16h5_create();
  impl->textures.resize(impl->family->num_apriltag_ids());
  for (int id : impl->family->kept_ids()) {
    for (int level = 0; level < kNumLevels; ++level) {
      const int ppc = kTextureLevels[level];
      impl->textures[id][level] = {
          ToLinearPremultiplied(SheetRgb(*impl->family, id, colors, april, ppc)), ppc};
    }
  }
  tag16h5_destroy(april);
  return std::unique_ptr<Dataset>(new Dataset(std::move(impl)));
}

// A random crop of a photograph, scaled to cover the frame, maybe mirrored,
// in linear light (CV_32FC3).
cv::Mat Dataset::Impl::LinearBackground(int photo, Rng& rng) const {
  const cv::Mat& source = photos[photo];
  const int w = options.width, h = options.height;
  const double cover =
      std::max(static_cast<double>(w) / source.cols, static_cast<double>(h) / source.rows);
  const double scale = cover * rng.Uniform(1.0, 1.6);
  const int crop_w = std::min(source.cols, static_cast<int>(std::ceil(w / scale)));
  const int crop_h = std::min(source.rows, static_cast<int>(std::ceil(h / scale)));
  const int x0 = static_cast<int>(rng.Uniform(0.0, source.cols - crop_w + 1.0));
  const int y0 = static_cast<int>(rng.Uniform(0.0, source.rows - crop_h + 1.0));
  cv::Mat resized;
  cv::resize(source(cv::Rect(std::min(x0, source.cols - crop_w), std::min(y0, source.rows - crop_h),
                             crop_w, crop_h)),
             resized, cv::Size(w, h), 0, 0, cv::INTER_AREA);
  if (rng.Uniform() < 0.5) cv::flip(resized, resized, 1);
  cv::Mat linear(h, w, CV_32FC3);
  for (int y = 0; y < h; ++y) {
    const cv::Vec3b* in = resized.ptr<cv::Vec3b>(y);
    cv::Vec3f* out = linear.ptr<cv::Vec3f>(y);
    for (int x = 0; x < w; ++x) {
      out[x] = {srgb_to_linear[in[x][0]], srgb_to_linear[in[x][1]], srgb_to_linear[in[x][2]]};
    }
  }
  return linear;
}

// Warps the sheet into `linear` (CV_32FC3) through a supersampled region of
// interest, lit with a gentle gradient (brightest over darkest in *gradient).
void Dataset::Impl::DrawSheet(const Camera& camera, int id, Rng& rng, cv::Mat* linear,
                              double* gradient) const {
  const int k = options.supersampling;
  const SheetFootprint footprint = Footprint(camera, kClassicLayout, linear->size(), k);
  const cv::Rect& roi = footprint.roi;
  if (roi.empty()) return;
  int level = kNumLevels - 1;
  for (int l = 0; l < kNumLevels; ++l) {
    if (kTextureLevels[l] >= footprint.needed_ppc) {
      level = l;
      break;
    }
  }
  const Texture& texture = textures[id][level];
  const cv::Mat sheet =
      WarpSheet(texture.linear, texture.pixels_per_cell, camera, kClassicLayout, roi, k);

  // Light falls off across the sheet (one side up to 25 % darker).
  const double gx = rng.Uniform(-0.25, 0.25) / std::max(1, roi.width);
  const double gy = rng.Uniform(-0.25, 0.25) / std::max(1, roi.height);
  const double top = 1.0 - std::abs(gx) * roi.width / 2.0 - std::abs(gy) * roi.height / 2.0;
  const double spread = std::abs(gx) * roi.width / 2.0 + std::abs(gy) * roi.height / 2.0;
  *gradient = (top + spread) / std::max(1e-9, top - spread);
  cv::Mat target = (*linear)(roi);
  for (int y = 0; y < roi.height; ++y) {
    const cv::Vec4f* s = sheet.ptr<cv::Vec4f>(y);
    cv::Vec3f* t = target.ptr<cv::Vec3f>(y);
    for (int x = 0; x < roi.width; ++x) {
      const float light =
          static_cast<float>(top + gx * (x - roi.width / 2.0) + gy * (y - roi.height / 2.0));
      const float keep = 1.0f - s[x][3];
      for (int c = 0; c < 3; ++c) t[x][c] = light * s[x][c] + keep * t[x][c];
    }
  }
}

// Exposure, colour condition, optics blur, gamma, sensor noise, JPEG.
cv::Mat Dataset::Impl::Finish(cv::Mat linear, FrameTruth* truth, ColorCondition condition, Rng& rng,
                              uint64_t noise_seed) const {
  truth->exposure = rng.Uniform(0.55, 1.1);
  cv::Vec3d gains(1.0, 1.0, 1.0);  // R, G, B.
  if (condition == ColorCondition::kColorCast) {
    for (int c = 0; c < 3; ++c) gains[c] = kCastGains[c] * rng.Uniform(0.92, 1.08);
  } else {
    for (int c = 0; c < 3; ++c) gains[c] = rng.Uniform(0.96, 1.04);
  }
  truth->red_gain = gains[0] / gains[1];
  truth->blue_gain = gains[2] / gains[1];
  cv::multiply(linear,
               cv::Scalar(gains[2] * truth->exposure, gains[1] * truth->exposure,
                          gains[0] * truth->exposure),
               linear);

  truth->blur_sigma_px = rng.Uniform(0.35, 1.1);
  cv::GaussianBlur(linear, linear, cv::Size(), truth->blur_sigma_px);
  if (rng.Uniform() < 0.25) {  // Some frames shake.
    truth->motion_blur_px = rng.Uniform(1.0, 5.0);
    cv::filter2D(linear, linear, -1, MotionKernel(truth->motion_blur_px, rng.Uniform(0.0, kPi)));
  }

  cv::Mat bgr = EncodeThrough(linear, linear_to_srgb);

  truth->noise_sigma = rng.Uniform(1.0, 4.0);
  cv::RNG noise_rng(noise_seed);
  cv::Mat noise(bgr.size(), CV_16SC3);
  noise_rng.fill(noise, cv::RNG::NORMAL, 0, truth->noise_sigma);
  cv::Mat wide;
  bgr.convertTo(wide, CV_16SC3);
  wide += noise;
  wide.convertTo(bgr, CV_8UC3);

  truth->jpeg_quality = static_cast<int>(rng.Uniform(70.0, 96.0));
  std::vector<uchar> bytes;
  cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, truth->jpeg_quality});
  return cv::imdecode(bytes, cv::IMREAD_COLOR);
}

Frame Dataset::Render(int index) const {
  return impl_->options.kind == DatasetKind::kCamera ? impl_->RenderCamera(index)
                                                     : impl_->RenderClassic(index);
}

FrameTruth Dataset::Truth(int index) const {
  return impl_->options.kind == DatasetKind::kCamera ? impl_->PlanCamera(index).truth
                                                     : impl_->RenderClassic(index).truth;
}

Frame Dataset::Impl::RenderClassic(int index) const {
  const DatasetOptions& o = options;
  Rng rng(FrameSeed(o.seed, index));
  Frame frame;
  FrameTruth& truth = frame.truth;
  truth.index = index;
  truth.kind = DatasetKind::kClassic;
  truth.condition = static_cast<ColorCondition>(index % kNumConditions);
  truth.cast = truth.condition == ColorCondition::kColorCast ? "tungsten" : "neutral";
  truth.print_chroma = kPrintChroma;
  truth.has_tags = rng.Uniform() >= o.tag_free_share;
  const std::vector<int>& kept = family->kept_ids();
  const int id = kept[rng.Index(static_cast<int>(kept.size()))];
  const int photo = rng.Index(static_cast<int>(photos.size()));
  truth.photo = photo_names[photo];
  const PathPoint path = CameraPath(o, index, rng);
  cv::Mat linear = LinearBackground(photo, rng);

  if (truth.has_tags) {
    const Camera camera = PlaceCamera(o, kClassicLayout, path, rng);
    DrawSheet(camera, id, rng, &linear, &truth.gradient);
    truth.family = family->name();
    truth.quiet_zone_cells = kClassicLayout.quiet_cells;
    truth.chromatag = TagTruthAt(camera, kClassicLayout.chroma_centre_x(), id);
    truth.apriltag = TagTruthAt(camera, kClassicLayout.april_centre_x(), id);
    truth.chromatag.family = truth.apriltag.family = truth.family;
  }
  frame.bgr = Finish(std::move(linear), &truth, truth.condition, rng, rng.Bits());
  return frame;
}

}  // namespace chromatag::bench
