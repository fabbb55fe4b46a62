// The geometry both data sets share: camera path and placement, the card's
// footprint and warp, truth, and the printed colours.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "chromatag/families/color.h"
#include "dataset_impl.h"

namespace chromatag::bench {
namespace {

// Triangle wave in [0, 1]: a camera path made of these has uniform marginals.
double Triangle(double x) { return 2.0 * std::abs(x - std::floor(x) - 0.5); }

Lab PrintedLab(const Lab& lab, Shade shade, double chroma) {
  if (shade == Shade::kBlack) return {std::max(lab.L, kPrintBlackL), lab.a, lab.b};
  if (shade == Shade::kWhite) return {std::min(lab.L, kPrintWhiteL), lab.a, lab.b};
  return {lab.L, lab.a * chroma, lab.b * chroma};
}

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

}  // namespace

uint64_t FrameSeed(uint64_t seed, int index) {
  uint64_t z = seed * 0x9E3779B97F4A7C15ull + static_cast<uint64_t>(index) + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

float SrgbToLinearF(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

cv::Matx33d Camera::ImageFromSheet() const {
  const cv::Matx33d k(fx, 0, cx, 0, fx, cy, 0, 0, 1);
  const cv::Matx33d rt(rotation(0, 0), rotation(0, 1), translation[0], rotation(1, 0),
                       rotation(1, 1), translation[1], rotation(2, 0), rotation(2, 1),
                       translation[2]);
  return k * rt;
}

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

Camera PlaceCamera(const DatasetOptions& options, const SheetLayout& layout, const PathPoint& path,
                   Rng& rng) {
  const double aim_x = rng.Uniform(layout.chroma_centre_x(), layout.april_centre_x());
  double distance = options.focal_px / path.size_px;
  const double margin = 4.0;
  const double half_x = layout.half_x(), half_y = layout.half_y();
  Camera camera;
  for (int attempt = 0; attempt < 200; ++attempt, distance *= 1.04) {
    camera = LookAt({aim_x, 0, 0}, distance, path.view_deg, path.azimuth_deg, path.roll_deg,
                    options.focal_px);
    double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
    bool in_front = true;
    for (double sx : {-half_x, half_x}) {
      for (double sy : {-half_y, half_y}) {
        const cv::Vec3d p = camera.rotation * cv::Vec3d(sx, sy, 0) + camera.translation;
        in_front = in_front && p[2] > 0.2;
        const cv::Point2d q = camera.Project({sx, sy, 0});
        min_x = std::min(min_x, q.x), max_x = std::max(max_x, q.x);
        min_y = std::min(min_y, q.y), max_y = std::max(max_y, q.y);
      }
    }
    const double room_x = options.width - 1 - 2 * margin - (max_x - min_x);
    const double room_y = options.height - 1 - 2 * margin - (max_y - min_y);
    if (in_front && room_x >= 0 && room_y >= 0) {
      camera.cx = margin - min_x + rng.Uniform(0.0, room_x);
      camera.cy = margin - min_y + rng.Uniform(0.0, room_y);
      break;
    }
  }
  return camera;
}

TagTruth TagTruthAt(const Camera& camera, double centre_x, int id) {
  TagTruth truth;
  truth.id = id;
  const auto corners = SquareCorners(centre_x);
  for (int i = 0; i < 4; ++i) truth.corners[i] = camera.Project(corners[i]);
  truth.size_px = QuadSizePx(truth.corners);
  const cv::Vec3d centre = camera.rotation * cv::Vec3d(centre_x, 0, 0) + camera.translation;
  const cv::Vec3d normal(camera.rotation(0, 2), camera.rotation(1, 2), camera.rotation(2, 2));
  const double c = std::clamp(normal.dot(centre) / cv::norm(centre), -1.0, 1.0);
  truth.view_angle_deg = std::acos(c) * 180.0 / kPi;
  // The sheet frame has y down and z into the sheet: the tag frame is it
  // turned half a turn about x.
  truth.rotation = camera.rotation * cv::Matx33d(1, 0, 0, 0, -1, 0, 0, 0, -1);
  truth.translation = centre;
  truth.fx = camera.fx;
  truth.cx = camera.cx;
  truth.cy = camera.cy;
  return truth;
}

SheetFootprint Footprint(const Camera& camera, const SheetLayout& layout, cv::Size frame_size,
                         int supersampling) {
  std::vector<cv::Point2d> outline;
  for (double sx : {-layout.half_x(), layout.half_x()}) {
    for (double sy : {-layout.half_y(), layout.half_y()}) {
      outline.push_back(camera.Project({sx, sy, 0}));
    }
  }
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const auto& p : outline) {
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
  }
  const cv::Rect frame(0, 0, frame_size.width, frame_size.height);
  SheetFootprint footprint;
  footprint.roi = cv::Rect(cv::Point(static_cast<int>(std::floor(min_x)) - 2,
                                     static_cast<int>(std::floor(min_y)) - 2),
                           cv::Point(static_cast<int>(std::ceil(max_x)) + 3,
                                     static_cast<int>(std::ceil(max_y)) + 3)) &
                  frame;
  double longest_side = 0.0;
  for (int i = 0; i < 4; ++i) {
    const int j = (i + 1) % 4;
    const int order[4] = {0, 1, 3, 2};  // outline is in grid order; walk it round.
    longest_side = std::max(longest_side, cv::norm(outline[order[i]] - outline[order[j]]));
  }
  footprint.needed_ppc = supersampling * longest_side / layout.sheet_cells_x();
  return footprint;
}

cv::Mat WarpSheet(const cv::Mat& texture, int ppc_int, const Camera& camera,
                  const SheetLayout& layout, const cv::Rect& roi, int k) {
  const double ppc = ppc_int;
  const int square = layout.square_cells;
  // Texture pixel centres to sheet units, sheet to image, image to the
  // supersampled region (pixel centres at integers throughout).
  const cv::Matx33d sheet_from_texture(
      1.0 / (square * ppc), 0, (0.5 / ppc - layout.sheet_cells_x() / 2.0) / square, 0,
      1.0 / (square * ppc), (0.5 / ppc - layout.sheet_cells_y() / 2.0) / square, 0, 0, 1);
  const cv::Matx33d super_from_image(k, 0, k * (0.5 - roi.x) - 0.5, 0, k, k * (0.5 - roi.y) - 0.5,
                                     0, 0, 1);
  const cv::Matx33d warp = super_from_image * camera.ImageFromSheet() * sheet_from_texture;
  cv::Mat super;
  cv::warpPerspective(texture, super, cv::Mat(warp), cv::Size(roi.width * k, roi.height * k),
                      cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar::all(0));
  cv::Mat sheet;
  cv::resize(super, sheet, roi.size(), 0, 0, cv::INTER_AREA);
  return sheet;
}

cv::Mat MotionKernel(double length_px, double angle) {
  const int size = 2 * static_cast<int>(std::ceil(length_px / 2)) + 1;
  cv::Mat kernel = cv::Mat::zeros(size, size, CV_32F);
  const double c = (size - 1) / 2.0, half = length_px / 2.0;
  cv::line(kernel, cv::Point2d(c - half * std::cos(angle), c - half * std::sin(angle)) * 16,
           cv::Point2d(c + half * std::cos(angle), c + half * std::sin(angle)) * 16,
           cv::Scalar(1.0), 1, cv::LINE_AA, 4);
  kernel /= cv::sum(kernel)[0];
  return kernel;
}

cv::Mat EncodeThrough(const cv::Mat& linear, const std::vector<uint8_t>& table) {
  const float steps = static_cast<float>(table.size() - 1);
  cv::Mat bgr(linear.size(), CV_8UC3);
  for (int y = 0; y < linear.rows; ++y) {
    const cv::Vec3f* in = linear.ptr<cv::Vec3f>(y);
    cv::Vec3b* out = bgr.ptr<cv::Vec3b>(y);
    for (int x = 0; x < linear.cols; ++x) {
      for (int c = 0; c < 3; ++c) {
        out[x][c] = table[static_cast<int>(std::clamp(in[x][c], 0.0f, 1.0f) * steps + 0.5f)];
      }
    }
  }
  return bgr;
}

TagColors PrintedColors(const Palette& palette, double chroma) {
  Palette printed = palette;
  for (Shade shade : kAllShades) printed[shade] = PrintedLab(palette[shade], shade, chroma);
  return TagColors::FromPalette(printed);
}

cv::Mat AprilTagPicture(apriltag_family_t* family, int id) {
  image_u8_t* image = apriltag_to_image(family, id);
  cv::Mat cells(image->height, image->width, CV_8UC1);
  for (int y = 0; y < image->height; ++y) {
    for (int x = 0; x < image->width; ++x) {
      cells.at<uint8_t>(y, x) = image->buf[y * image->stride + x] != 0 ? 1 : 0;
    }
  }
  image_u8_destroy(image);
  return cells;
}

}  // namespace chromatag::bench
