#include "chromatag/bench/dataset.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <sstream>

#include "chromatag/families/color.h"
#include "chromatag/families/family.h"
#include "chromatag/families/palette.h"
#include "chromatag/generator/tag_renderer.h"

namespace chromatag::bench {
namespace {

constexpr double kPi = 3.14159265358979323846;

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

// The sheet: ChromaTag (black square, 2-cell white quiet zone) on the left,
// the AprilTag with the same quiet zone on the right, quiet zones touching:
// 20 x 10 cells of a 6-cell black square, so in tag units (black-square
// sides) the sheet spans [-5/3, 5/3] x [-5/6, 5/6].
constexpr int kTagCells = 10;    // One tag with its quiet zones.
constexpr int kSquareCells = 6;  // Black square of 16h5.
constexpr int kQuietCells = 2;
constexpr int kSheetCellsX = 2 * kTagCells;
constexpr int kSheetCellsY = kTagCells;
// Texture resolutions, pixels per cell; each frame picks the smallest one not
// coarser than its supersampled image (the largest is magnified a little).
constexpr int kTextureLevels[] = {2, 4, 8, 16, 32};
constexpr int kNumLevels = sizeof(kTextureLevels) / sizeof(kTextureLevels[0]);

// Colours as printed: inks are less saturated than the file, black ink is
// not black and paper not perfectly white (spec section 6 measured L* 14 for
// the authors' black). Applied alike to both tags.
constexpr double kPrintChroma = 0.85;
constexpr double kPrintBlackL = 14.0;
constexpr double kPrintWhiteL = 95.0;

// Tungsten-like uncorrected cast (linear R, G, B gains) for NWB frames.
const cv::Vec3d kCastGains(1.0, 0.74, 0.42);

// A small portable random source: frames must not depend on the standard
// library's distributions, which differ between implementations.
class Rng {
 public:
  explicit Rng(uint64_t seed) : engine_(seed) {}
  double Uniform(double lo = 0.0, double hi = 1.0) {
    return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * (1.0 / 9007199254740992.0);
  }
  int Index(int n) { return static_cast<int>(Uniform() * n) % n; }
  uint64_t Bits() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

uint64_t FrameSeed(uint64_t seed, int index) {
  // SplitMix64 finaliser over (seed, index): independent streams per frame.
  uint64_t z = seed * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(index) + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// Triangle wave in [0, 1]: a camera path made of these has uniform marginals.
double Triangle(double x) { return 2.0 * std::abs(x - std::floor(x) - 0.5); }

float SrgbToLinearF(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

struct Texture {
  cv::Mat linear;  // CV_32FC4: premultiplied linear B, G, R, alpha.
  int pixels_per_cell = 0;
};

Lab PrintedLab(const Lab& lab, Shade shade) {
  if (shade == Shade::kBlack) return {std::max(lab.L, kPrintBlackL), lab.a, lab.b};
  if (shade == Shade::kWhite) return {std::min(lab.L, kPrintWhiteL), lab.a, lab.b};
  return {lab.L, lab.a * kPrintChroma, lab.b * kPrintChroma};
}

TagColors PrintedColors(const Palette& palette) {
  Palette printed = palette;
  for (Shade shade : kAllShades) printed[shade] = PrintedLab(palette[shade], shade);
  return TagColors::FromPalette(printed);
}

// libapriltag's own picture of the tag (1-cell white border), 2-cell quiet
// zone, one byte per cell: 0 black, 1 white.
cv::Mat AprilTagCells(apriltag_family_t* family, int id) {
  image_u8_t* image = apriltag_to_image(family, id);
  cv::Mat cells(kTagCells, kTagCells, CV_8UC1, cv::Scalar(1));
  const int pad = (kTagCells - image->width) / 2;
  for (int y = 0; y < image->height; ++y) {
    for (int x = 0; x < image->width; ++x) {
      cells.at<uint8_t>(y + pad, x + pad) = image->buf[y * image->stride + x] != 0 ? 1 : 0;
    }
  }
  image_u8_destroy(image);
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
  draw.quiet_zone_cells = kQuietCells;
  const RgbImage chroma = RasterizeTag(family, id, colors, ppc, draw);
  assert(chroma.width == kTagCells * ppc && chroma.height == kTagCells * ppc);
  cv::Mat sheet(kSheetCellsY * ppc, kSheetCellsX * ppc, CV_8UC3);
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

struct Camera {
  cv::Matx33d rotation;  // camera_from_sheet.
  cv::Vec3d translation;
  double fx = 0, cx = 0, cy = 0;

  cv::Point2d Project(const cv::Vec3d& sheet_point) const {
    const cv::Vec3d p = rotation * sheet_point + translation;
    return {fx * p[0] / p[2] + cx, fx * p[1] / p[2] + cy};
  }
  // Maps sheet points (x, y, 0) in tag units to image pixels.
  cv::Matx33d ImageFromSheet() const {
    const cv::Matx33d k(fx, 0, cx, 0, fx, cy, 0, 0, 1);
    const cv::Matx33d rt(rotation(0, 0), rotation(0, 1), translation[0], rotation(1, 0),
                         rotation(1, 1), translation[1], rotation(2, 0), rotation(2, 1),
                         translation[2]);
    return k * rt;
  }
};

// Sheet frame: x right, y down along the sheet, z into it (away from the
// viewer). The camera looks at `target` from `distance` along a direction
// `view_deg` off the normal, turned by `azimuth_deg` about it, and rolls by
// `roll_deg` about its optical axis.
Camera LookAt(const cv::Vec3d& target, double distance, double view_deg, double azimuth_deg,
              double roll_deg, double focal_px) {
  const double v = view_deg * kPi / 180.0, az = azimuth_deg * kPi / 180.0;
  const cv::Vec3d to_camera(std::sin(v) * std::cos(az), std::sin(v) * std::sin(az), -std::cos(v));
  const cv::Vec3d centre = target + distance * to_camera;
  const cv::Vec3d z = -to_camera;
  cv::Vec3d x = cv::Vec3d(1, 0, 0) - z.dot(cv::Vec3d(1, 0, 0)) * z;
  if (cv::norm(x) < 1e-6) x = cv::Vec3d(0, 1, 0) - z.dot(cv::Vec3d(0, 1, 0)) * z;
  x = cv::normalize(x);
  cv::Vec3d y = z.cross(x);
  const double r = roll_deg * kPi / 180.0;
  const cv::Vec3d xr = std::cos(r) * x + std::sin(r) * y;
  const cv::Vec3d yr = z.cross(xr);
  Camera camera;
  camera.rotation = cv::Matx33d(xr[0], xr[1], xr[2], yr[0], yr[1], yr[2], z[0], z[1], z[2]);
  camera.translation = -(camera.rotation * centre);
  camera.fx = focal_px;
  return camera;
}

// Black-square corners of the tag centred at sheet x = `centre_x`, spec order.
std::array<cv::Vec3d, 4> SquareCorners(double centre_x) {
  return {cv::Vec3d(centre_x - 0.5, -0.5, 0), cv::Vec3d(centre_x + 0.5, -0.5, 0),
          cv::Vec3d(centre_x + 0.5, 0.5, 0), cv::Vec3d(centre_x - 0.5, 0.5, 0)};
}

constexpr double kChromaCentreX = -static_cast<double>(kTagCells) / (2 * kSquareCells);
constexpr double kAprilCentreX = -kChromaCentreX;
constexpr double kSheetHalfX = static_cast<double>(kSheetCellsX) / (2 * kSquareCells);
constexpr double kSheetHalfY = static_cast<double>(kSheetCellsY) / (2 * kSquareCells);

TagTruth Truth(const Camera& camera, double centre_x, int id) {
  TagTruth truth;
  truth.id = id;
  const auto corners = SquareCorners(centre_x);
  for (int i = 0; i < 4; ++i) truth.corners[i] = camera.Project(corners[i]);
  truth.size_px = QuadSizePx(truth.corners);
  const cv::Vec3d centre = camera.rotation * cv::Vec3d(centre_x, 0, 0) + camera.translation;
  const cv::Vec3d normal(camera.rotation(0, 2), camera.rotation(1, 2), camera.rotation(2, 2));
  const double c = std::clamp(normal.dot(centre) / cv::norm(centre), -1.0, 1.0);
  truth.view_angle_deg = std::acos(c) * 180.0 / kPi;
  return truth;
}

// Where the camera path is at frame `index`: smooth triangle waves with
// incommensurate periods (in frames) and seeded phases, plus a little jitter.
// Roll sweeps 0-180 degrees like the paper's servo.
struct PathPoint {
  double size_px, view_deg, azimuth_deg, roll_deg;
};

PathPoint CameraPath(const DatasetOptions& options, int index, Rng& rng) {
  Rng phases(FrameSeed(options.seed, -1));
  const double p_size = phases.Uniform(), p_view = phases.Uniform(), p_az = phases.Uniform(),
               p_roll = phases.Uniform();
  const double t = index;
  const double log_lo = std::log(options.min_size_px), log_hi = std::log(options.max_size_px);
  PathPoint point;
  const double s = std::clamp(Triangle(t / 97.31 + p_size) + rng.Uniform(-0.02, 0.02), 0.0, 1.0);
  point.size_px = std::exp(log_lo + (log_hi - log_lo) * s);
  const double v = std::clamp(Triangle(t / 61.73 + p_view) + rng.Uniform(-0.02, 0.02), 0.0, 1.0);
  point.view_deg = options.max_view_angle_deg * v;
  point.azimuth_deg = 360.0 * (t / 41.17 + p_az);
  point.roll_deg = 180.0 * Triangle(t / 53.89 + p_roll) + rng.Uniform(-3.0, 3.0);
  return point;
}

}  // namespace

const char* ConditionName(ColorCondition condition) {
  return condition == ColorCondition::kWhiteBalanced ? "WB" : "NWB";
}

bool DatasetOptions::IsValid(std::string* error) const {
  std::ostringstream why;
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

struct Dataset::Impl {
  DatasetOptions options;
  std::shared_ptr<const TagFamily> family;
  std::vector<std::string> photo_names;
  std::vector<cv::Mat> photos;  // CV_8UC3 BGR.
  // textures[id][level], for kept IDs only.
  std::vector<std::array<Texture, kNumLevels>> textures;
  std::vector<float> srgb_to_linear;    // 256 entries.
  std::vector<uint8_t> linear_to_srgb;  // 4096 entries over [0, 1].

  cv::Mat LinearBackground(int photo, Rng& rng) const;
  void DrawSheet(const Camera& camera, int id, Rng& rng, cv::Mat* linear) const;
  cv::Mat Finish(cv::Mat linear, FrameTruth* truth, ColorCondition condition, Rng& rng,
                 uint64_t noise_seed) const;
};

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
  const TagColors colors = PrintedColors(*palette);
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
// interest, lit with a gentle gradient.
void Dataset::Impl::DrawSheet(const Camera& camera, int id, Rng& rng, cv::Mat* linear) const {
  const int k = options.supersampling;
  const cv::Matx33d image_from_sheet = camera.ImageFromSheet();
  std::vector<cv::Point2d> outline;
  for (double sx : {-kSheetHalfX, kSheetHalfX}) {
    for (double sy : {-kSheetHalfY, kSheetHalfY}) outline.push_back(camera.Project({sx, sy, 0}));
  }
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const auto& p : outline) {
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  }
  const cv::Rect frame(0, 0, linear->cols, linear->rows);
  const cv::Rect roi = cv::Rect(cv::Point(static_cast<int>(std::floor(min_x)) - 2,
                                          static_cast<int>(std::floor(min_y)) - 2),
                                cv::Point(static_cast<int>(std::ceil(max_x)) + 3,
                                          static_cast<int>(std::ceil(max_y)) + 3)) &
                       frame;
  if (roi.empty()) return;

  // Finest sampling the sheet gets in the supersampled image, pixels per cell.
  double longest_side = 0.0;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const int order[4] = {0, 1, 3, 2};  // outline is in grid order; walk it round.
    longest_side = std::max(longest_side, cv::norm(outline[order[i]] - outline[order[j]]));
  }
  const double needed_ppc = k * longest_side / kSheetCellsX;
  int level = kNumLevels - 1;
  for (int l = 0; l < kNumLevels; ++l) {
    if (kTextureLevels[l] >= needed_ppc) {
      level = l;
      break;
    }
  }
  const Texture& texture = textures[id][level];
  const double ppc = texture.pixels_per_cell;
  // Texture pixel centres to sheet units, sheet to image, image to the
  // supersampled region (pixel centres at integers throughout).
  const cv::Matx33d sheet_from_texture(
      1.0 / (kSquareCells * ppc), 0, (0.5 / ppc - kSheetCellsX / 2.0) / kSquareCells, 0,
      1.0 / (kSquareCells * ppc), (0.5 / ppc - kSheetCellsY / 2.0) / kSquareCells, 0, 0, 1);
  const cv::Matx33d super_from_image(k, 0, k * (0.5 - roi.x) - 0.5, 0, k, k * (0.5 - roi.y) - 0.5,
                                     0, 0, 1);
  const cv::Matx33d warp = super_from_image * image_from_sheet * sheet_from_texture;
  cv::Mat super;
  cv::warpPerspective(texture.linear, super, cv::Mat(warp), cv::Size(roi.width * k, roi.height * k),
                      cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  cv::Mat sheet;
  cv::resize(super, sheet, roi.size(), 0, 0, cv::INTER_AREA);

  // Light falls off across the sheet (one side up to 25 % darker).
  const double gx = rng.Uniform(-0.25, 0.25) / std::max(1, roi.width);
  const double gy = rng.Uniform(-0.25, 0.25) / std::max(1, roi.height);
  const double top = 1.0 - std::abs(gx) * roi.width / 2.0 - std::abs(gy) * roi.height / 2.0;
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
  cv::multiply(linear,
               cv::Scalar(gains[2] * truth->exposure, gains[1] * truth->exposure,
                          gains[0] * truth->exposure),
               linear);

  truth->blur_sigma_px = rng.Uniform(0.35, 1.1);
  cv::GaussianBlur(linear, linear, cv::Size(), truth->blur_sigma_px);
  if (rng.Uniform() < 0.25) {  // Some frames shake.
    truth->motion_blur_px = rng.Uniform(1.0, 5.0);
    const double angle = rng.Uniform(0.0, kPi);
    const int size = 2 * static_cast<int>(std::ceil(truth->motion_blur_px / 2)) + 1;
    cv::Mat kernel = cv::Mat::zeros(size, size, CV_32F);
    const double c = (size - 1) / 2.0, half = truth->motion_blur_px / 2.0;
    cv::line(kernel, cv::Point2d(c - half * std::cos(angle), c - half * std::sin(angle)) * 16,
             cv::Point2d(c + half * std::cos(angle), c + half * std::sin(angle)) * 16,
             cv::Scalar(1.0), 1, cv::LINE_AA, 4);
    kernel /= cv::sum(kernel)[0];
    cv::filter2D(linear, linear, -1, kernel);
  }

  cv::Mat bgr(linear.size(), CV_8UC3);
  for (int y = 0; y < linear.rows; ++y) {
    const cv::Vec3f* in = linear.ptr<cv::Vec3f>(y);
    cv::Vec3b* out = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < linear.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v = std::clamp(in[x][c], 0.0f, 1.0f);
        out[x][c] = linear_to_srgb[static_cast<int>(v * 4095.0f + 0.5f)];
      }
    }
  }

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
  const Impl& d = *impl_;
  const DatasetOptions& o = d.options;
  Rng rng(FrameSeed(o.seed, index));
  Frame frame;
  FrameTruth& truth = frame.truth;
  truth.index = index;
  truth.condition = static_cast<ColorCondition>(index % kNumConditions);
  truth.has_tags = rng.Uniform() >= o.tag_free_share;
  const std::vector<int>& kept = d.family->kept_ids();
  const int id = kept[rng.Index(static_cast<int>(kept.size()))];
  const int photo = rng.Index(static_cast<int>(d.photos.size()));
  truth.photo = d.photo_names[photo];
  const PathPoint path = CameraPath(o, index, rng);
  cv::Mat linear = d.LinearBackground(photo, rng);

  if (truth.has_tags) {
    // Aim at one of the two tags or between them; back off until the whole
    // sheet fits with a margin, then place it at random in the frame by
    // moving the principal point.
    const double aim_x = rng.Uniform(kChromaCentreX, kAprilCentreX);
    double distance = o.focal_px / path.size_px;
    const double margin = 4.0;
    Camera camera;
    for (int attempt = 0; attempt < 200; ++attempt, distance *= 1.04) {
      camera = LookAt({aim_x, 0, 0}, distance, path.view_deg, path.azimuth_deg, path.roll_deg,
                      o.focal_px);
      double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
      bool in_front = true;
      for (double sx : {-kSheetHalfX, kSheetHalfX}) {
        for (double sy : {-kSheetHalfY, kSheetHalfY}) {
          const cv::Vec3d p = camera.rotation * cv::Vec3d(sx, sy, 0) + camera.translation;
          in_front = in_front && p[2] > 0.2;
          const cv::Point2d q = camera.Project({sx, sy, 0});
          min_x = std::min(min_x, q.x), max_x = std::max(max_x, q.x);
          min_y = std::min(min_y, q.y), max_y = std::max(max_y, q.y);
        }
      }
      const double room_x = o.width - 1 - 2 * margin - (max_x - min_x);
      const double room_y = o.height - 1 - 2 * margin - (max_y - min_y);
      if (in_front && room_x >= 0 && room_y >= 0) {
        camera.cx = margin - min_x + rng.Uniform(0.0, room_x);
        camera.cy = margin - min_y + rng.Uniform(0.0, room_y);
        break;
      }
    }
    d.DrawSheet(camera, id, rng, &linear);
    truth.chromatag = Truth(camera, kChromaCentreX, id);
    truth.apriltag = Truth(camera, kAprilCentreX, id);
  }
  frame.bgr = d.Finish(std::move(linear), &truth, truth.condition, rng, rng.Bits());
  return frame;
}

}  // namespace chromatag::bench
