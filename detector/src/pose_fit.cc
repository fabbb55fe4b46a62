#include "pose_fit.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "chromatag/detector/camera.h"

#include "geometry.h"
#include "refine_corners.h"

namespace chromatag::internal {
namespace {

// Levenberg-Marquardt: at most this many iterations, stopping when a step
// (the rotation's radians and the translation's metres together) is
// shorter than kConvergedStep.
constexpr int kMaxIterations = 30;
constexpr double kConvergedStep = 1e-10;

// The corners of a square of side `side` centred on the tag origin, in the
// spec's tag frame (x right, y up): top-left, then clockwise as seen from the
// front, matching Detection::corners (and SOLVEPNP_IPPE_SQUARE's order).
void AddSquare(double side, std::vector<cv::Point3d>* points) {
  const double h = 0.5 * side;
  points->push_back({-h, h, 0});
  points->push_back({h, h, 0});
  points->push_back({h, -h, 0});
  points->push_back({-h, -h, 0});
}

}  // namespace

std::vector<cv::Point3d> TagRingCorners(const TagFamily& family, double tag_size) {
  // The black square, then the green/black square (d of the d + 2 cells) and
  // the red/green one (d - 2).
  const double cells = family.black_square_cells();
  std::vector<cv::Point3d> object;
  AddSquare(tag_size, &object);
  AddSquare(tag_size * (cells - 2) / cells, &object);
  AddSquare(tag_size * (cells - 4) / cells, &object);
  return object;
}

bool UndistortedRingCorners(const Detection& detection, const CameraIntrinsics& camera,
                            std::vector<cv::Point2d>* undistorted, std::string* error) {
  std::vector<cv::Point2d> image(detection.corners.begin(), detection.corners.end());
  image.insert(image.end(), detection.green_corners.begin(), detection.green_corners.end());
  image.insert(image.end(), detection.red_corners.begin(), detection.red_corners.end());
  for (const cv::Point2d& p : image) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      if (error) *error = "the detection's corners are not finite";
      return false;
    }
  }
  *undistorted = UndistortPoints(camera, image);
  for (const cv::Point2d& p : *undistorted) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      if (error) *error = "a corner lies beyond the range of the camera's lens model";
      return false;
    }
  }
  return true;
}

double Reprojection::Cost(const cv::Matx33d& r, const cv::Vec3d& t) const {
  double sum = 0;
  for (size_t i = 0; i < object_.size(); ++i) {
    const cv::Vec3d p = r * cv::Vec3d(object_[i].x, object_[i].y, object_[i].z) + t;
    if (!(p[2] > 0)) return std::numeric_limits<double>::infinity();
    const double du = k_(0, 0) * p[0] / p[2] + k_(0, 2) - image_[i].x;
    const double dv = k_(1, 1) * p[1] / p[2] + k_(1, 2) - image_[i].y;
    sum += du * du + dv * dv;
  }
  return sum;
}

double Reprojection::Rms(const cv::Matx33d& r, const cv::Vec3d& t) const {
  return object_.empty() ? 0.0 : std::sqrt(Cost(r, t) / static_cast<double>(object_.size()));
}

// The normal equations of the residuals' first-order change under a small
// rotation w composed onto r (exp([w]x) r) and a shift of t: parameters
// (w, dt). False when a point lies behind the camera.
bool Reprojection::Normal(const cv::Matx33d& r, const cv::Vec3d& t, cv::Matx66d* jtj,
                          cv::Vec6d* jte) const {
  *jtj = cv::Matx66d::zeros();
  *jte = cv::Vec6d::all(0);
  for (size_t i = 0; i < object_.size(); ++i) {
    const cv::Vec3d q = r * cv::Vec3d(object_[i].x, object_[i].y, object_[i].z);
    const cv::Vec3d p = q + t;
    if (!(p[2] > 0)) return false;
    const double fx = k_(0, 0), fy = k_(1, 1), z = p[2];
    const double e[2] = {fx * p[0] / z + k_(0, 2) - image_[i].x,
                         fy * p[1] / z + k_(1, 2) - image_[i].y};
    // d(u, v)/dp.
    const cv::Vec3d du(fx / z, 0, -fx * p[0] / (z * z)), dv(0, fy / z, -fy * p[1] / (z * z));
    for (int row = 0; row < 2; ++row) {
      const cv::Vec3d& g = row == 0 ? du : dv;
      // dp/dw = -[q]x, so (dp/dw)^T g = q x g; dp/dt = I.
      const cv::Vec3d gw = q.cross(g);
      const cv::Vec6d j(gw[0], gw[1], gw[2], g[0], g[1], g[2]);
      *jtj += j * j.t();
      *jte += e[row] * j;
    }
  }
  return true;
}

void Reprojection::Refine(PoseFit* fit) const {
  double cost = Cost(fit->rotation, fit->translation);
  double lambda = 1e-3;
  for (int iteration = 0; iteration < kMaxIterations && std::isfinite(cost); ++iteration) {
    cv::Matx66d jtj;
    cv::Vec6d jte;
    if (!Normal(fit->rotation, fit->translation, &jtj, &jte)) break;
    bool improved = false;
    cv::Vec6d step;
    while (lambda < 1e12) {
      cv::Matx66d damped = jtj;
      for (int i = 0; i < 6; ++i) damped(i, i) += lambda * std::max(jtj(i, i), 1e-12);
      if (!cv::solve(damped, -jte, step, cv::DECOMP_CHOLESKY)) {
        lambda *= 10;
        continue;
      }
      cv::Matx33d delta;
      cv::Rodrigues(cv::Vec3d(step[0], step[1], step[2]), delta);
      const cv::Matx33d r = delta * fit->rotation;
      const cv::Vec3d t = fit->translation + cv::Vec3d(step[3], step[4], step[5]);
      const double next = Cost(r, t);
      if (next < cost) {
        fit->rotation = r;
        fit->translation = t;
        cost = next;
        lambda = std::max(lambda / 10, 1e-9);
        improved = true;
        break;
      }
      lambda *= 10;
    }
    if (!improved || cv::norm(step) < kConvergedStep) break;
  }
  fit->rms_px = std::sqrt(cost / static_cast<double>(object_.size()));
}

namespace {

// The twelve ring corners placed from the four outer ones (the detector's
// way: one and two cells inside them, through the homography of the
// square), lens distortion then taken out.
std::vector<cv::Point2d> RingFromCorners(const Quad& corners, int cells,
                                         const CameraIntrinsics& camera) {
  const cv::Matx33d h = UnitSquareToQuad(corners);
  std::vector<cv::Point2d> ring(corners.begin(), corners.end());
  for (int inset = 1; inset <= 2; ++inset) {
    const Quad inner = InsetSquare(h, inset / static_cast<double>(cells));
    ring.insert(ring.end(), inner.begin(), inner.end());
  }
  return UndistortPoints(camera, ring);
}

// d(projection of `object` under r, t) / d(w, t), two rows per point, with
// the residuals (projection - image) into *residual.
void ProjectionJacobian(const std::vector<cv::Point3d>& object,
                        const std::vector<cv::Point2d>& image, const cv::Matx33d& r,
                        const cv::Vec3d& t, const cv::Matx33d& k, cv::Mat* jacobian,
                        cv::Mat* residual) {
  const int n = static_cast<int>(object.size());
  *jacobian = cv::Mat::zeros(2 * n, 6, CV_64F);
  *residual = cv::Mat::zeros(2 * n, 1, CV_64F);
  for (int i = 0; i < n; ++i) {
    const cv::Vec3d q = r * cv::Vec3d(object[i].x, object[i].y, object[i].z);
    const cv::Vec3d p = q + t;
    const double fx = k(0, 0), fy = k(1, 1), z = p[2];
    residual->at<double>(2 * i) = fx * p[0] / z + k(0, 2) - image[i].x;
    residual->at<double>(2 * i + 1) = fy * p[1] / z + k(1, 2) - image[i].y;
    const cv::Vec3d du(fx / z, 0, -fx * p[0] / (z * z)), dv(0, fy / z, -fy * p[1] / (z * z));
    for (int row = 0; row < 2; ++row) {
      const cv::Vec3d& g = row == 0 ? du : dv;
      const cv::Vec3d gw = q.cross(g);  // As Reprojection::Normal.
      double* out = jacobian->ptr<double>(2 * i + row);
      for (int c = 0; c < 3; ++c) {
        out[c] = gw[c];
        out[3 + c] = g[c];
      }
    }
  }
}

// The outer corners' misfit under (r, t), weighed by their covariance
// (carried to undistorted pixels): a chi-square with eight terms per tag.
double CornerChiSquare(const std::vector<const CornerNoise*>& noise, const cv::Matx33d& r,
                       const cv::Vec3d& t, const cv::Matx33d& k) {
  double chi2 = 0.0;
  for (const CornerNoise* tag : noise) {
    cv::Mat j, e;
    const std::vector<cv::Point3d> outer(tag->object.begin(), tag->object.begin() + 4);
    const std::vector<cv::Point2d> seen(tag->image.begin(), tag->image.begin() + 4);
    ProjectionJacobian(outer, seen, r, t, k, &j, &e);
    const cv::Mat d = cv::Mat(tag->image_from_corners).rowRange(0, 8);
    const cv::Mat covariance = d * cv::Mat(tag->covariance) * d.t();
    cv::Mat weighed;
    if (!cv::solve(covariance, e, weighed, cv::DECOMP_CHOLESKY)) return 0.0;
    chi2 += e.dot(weighed);
  }
  return chi2;
}

// How much larger the corners' covariance is taken when weighing the rival
// solution. Corner errors have heavier tails than the covariance's Gaussian
// (a pixel's sampling, JPEG's blocks), and a Gaussian likelihood gives the
// mirrored tilt too little weight. Measured on the camera set (per-axis
// spread of error over sigma): with 1, tags under 30 px, which now and then
// take the mirrored tilt, reach 5.9, 5.4 and 1.3 about x, y and z; with 4,
// 0.95, 0.82 and 0.93, and the larger tags' figures move by 0.01 at most
// (their rival is seldom near).
constexpr double kRivalNoiseScale = 4.0;

// The 95 % (and 5 %) points of a chi-square with `dof` degrees of freedom
// (Wilson and Hilferty's cube-root approximation: within 1 % from two
// degrees up).
double ChiSquarePoint(double dof, double z) {
  const double a = 2.0 / (9.0 * dof);
  const double root = 1.0 - a + z * std::sqrt(a);
  return dof * root * root * root;
}
double ChiSquare95(double dof) { return ChiSquarePoint(dof, 1.6449); }
double ChiSquare05(double dof) { return ChiSquarePoint(dof, -1.6449); }

// How much the corners' noise is scaled for the pose's covariance, from the
// fit's residuals (sum of squares `residual_ss`) against what the noise
// would leave (`expected`), over eight corner coordinates a tag less the
// pose's six: residuals that fail a 95 % chi-square test (a lens model or a
// board that is off) take over the scale; residuals under its 5 % point
// lower it, on kMinTagsToLowerNoise tags or more, to no less than
// kLowestNoiseScale.
double NoiseScale(double residual_ss, double expected, size_t tags) {
  const double dof = 8.0 * static_cast<double>(tags) - 6.0;
  if (!(expected > 0) || !(dof > 0)) return 1.0;
  const double ratio = residual_ss / expected;
  if (ratio > ChiSquare95(dof) / dof) return ratio;
  if (ratio < ChiSquare05(dof) / dof && tags >= kMinTagsToLowerNoise)
    return std::max(kLowestNoiseScale, ratio);
  return 1.0;
}

// (w, t) -> ROS's (t, w).
cv::Matx66d RosOrder(const cv::Mat& covariance) {
  cv::Matx66d out;
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j < 6; ++j) out(i, j) = covariance.at<double>((i + 3) % 6, (j + 3) % 6);
  }
  return out;
}

}  // namespace

bool TagCornerNoise(const Detection& detection, const CameraIntrinsics& camera,
                    std::vector<cv::Point3d> object, CornerNoise* noise) {
  if (!UndistortedRingCorners(detection, camera, &noise->image, nullptr)) return false;
  noise->object = std::move(object);
  const int cells = detection.family->black_square_cells();
  constexpr double kStep = 1e-3;  // Pixels: central differences.
  for (int c = 0; c < 8; ++c) {
    Quad plus = detection.corners, minus = detection.corners;
    (c % 2 == 0 ? plus[c / 2].x : plus[c / 2].y) += kStep;
    (c % 2 == 0 ? minus[c / 2].x : minus[c / 2].y) -= kStep;
    const std::vector<cv::Point2d> a = RingFromCorners(plus, cells, camera);
    const std::vector<cv::Point2d> b = RingFromCorners(minus, cells, camera);
    for (int i = 0; i < 12; ++i) {
      noise->image_from_corners(2 * i, c) = (a[i].x - b[i].x) / (2 * kStep);
      noise->image_from_corners(2 * i + 1, c) = (a[i].y - b[i].y) / (2 * kStep);
    }
  }
  for (int r = 0; r < 24; ++r) {
    for (int c = 0; c < 8; ++c) {
      if (!std::isfinite(noise->image_from_corners(r, c))) return false;
    }
  }
  noise->grow = QuadGrowth(detection.corners);
  noise->covariance = detection.corner_covariance;
  if (cv::norm(noise->covariance) == 0.0)
    noise->covariance =
        kUnknownCornerSigmaPx * kUnknownCornerSigmaPx * cv::Matx<double, 8, 8>::eye();
  return true;
}

cv::Matx66d PoseCovariance(const std::vector<const CornerNoise*>& noise, const PoseFit& fit,
                           const PoseFit* rival, const cv::Matx33d& k) {
  // The fit's parameters move with the image points as -(J^T J)^-1 J^T, and
  // the image points with the corners as image_from_corners (H): per tag,
  // M = J^T H, and the covariance is (J^T J)^-1 (sum M C M^T) (J^T J)^-1.
  // The errors the tags of a frame share add their terms between tags (each
  // tag's own covariance holds them within it): a shift of the frame, and
  // the share kSharedGrowShare of each tag's growth.
  cv::Mat jtj = cv::Mat::zeros(6, 6, CV_64F), middle = cv::Mat::zeros(6, 6, CV_64F);
  cv::Mat shift_x = cv::Mat::zeros(6, 1, CV_64F), shift_y = shift_x.clone(), grow = shift_x.clone(),
          grow_within = cv::Mat::zeros(6, 6, CV_64F), shift_within = grow_within.clone();
  double residual_ss = 0.0, image_variance = 0.0;
  for (const CornerNoise* tag : noise) {
    cv::Mat j, e;
    ProjectionJacobian(tag->object, tag->image, fit.rotation, fit.translation, k, &j, &e);
    const cv::Mat h(tag->image_from_corners), c(tag->covariance);
    const cv::Mat m = j.t() * h;
    jtj += j.t() * j;
    middle += m * c * m.t();
    const cv::Mat sx = m * cv::Mat(kQuadShiftX), sy = m * cv::Mat(kQuadShiftY);
    shift_x += sx;
    shift_y += sy;
    shift_within += sx * sx.t() + sy * sy.t();
    const cv::Mat g = m * cv::Mat(tag->grow);
    grow += g;
    grow_within += g * g.t();
    residual_ss += e.dot(e);
    image_variance += cv::trace(h * c * h.t())[0];
  }
  const double grow_px = kCornerNoise.grow_px;
  middle += kFrameShiftPx * kFrameShiftPx *
                (shift_x * shift_x.t() + shift_y * shift_y.t() - shift_within) +
            kSharedGrowShare * grow_px * grow_px * (grow * grow.t() - grow_within);
  cv::Mat inverse;
  if (cv::invert(jtj, inverse, cv::DECOMP_CHOLESKY) == 0.0)
    return cv::Matx66d::eye() * std::numeric_limits<double>::infinity();
  cv::Mat covariance = inverse * middle * inverse;
  // The residuals the corners' noise would leave: the image points'
  // variance less the share the fit absorbs.
  const double scale =
      NoiseScale(residual_ss, image_variance - cv::trace(inverse * middle)[0], noise.size());
  covariance *= scale;
  if (rival && AngleBetween(fit.rotation, rival->rotation) > kSameSolutionRadians) {
    // The rival's share: its likelihood against the fit's, from the outer
    // corners' misfit under each (the covariance scaled by kRivalNoiseScale).
    const double gap = (CornerChiSquare(noise, rival->rotation, rival->translation, k) -
                        CornerChiSquare(noise, fit.rotation, fit.translation, k)) /
                       (scale * kRivalNoiseScale);
    const double share = 1.0 / (1.0 + std::exp(std::min(0.5 * gap, 700.0)));
    cv::Vec3d w;
    cv::Rodrigues(Orthonormal(rival->rotation * fit.rotation.t()), w);
    const cv::Vec3d dt = rival->translation - fit.translation;
    const cv::Mat apart = (cv::Mat_<double>(6, 1) << w[0], w[1], w[2], dt[0], dt[1], dt[2]);
    covariance += share * apart * apart.t();
  }
  return RosOrder(covariance);
}

std::vector<PoseFit> TagPoseFits(const std::vector<cv::Point3d>& object,
                                 const std::vector<cv::Point2d>& image, const cv::Matx33d& k) {
  // Starting points, each refined on the twelve corners: both planar
  // solutions IPPE gives for the outer square (near frontal views the two
  // explain four corners almost equally, and the twelve tell them apart)...
  const std::vector<cv::Point3d> outer(object.begin(), object.begin() + 4);
  const std::vector<cv::Point2d> outer_image(image.begin(), image.begin() + 4);
  std::vector<cv::Mat> rvecs, tvecs;
  try {
    cv::solvePnPGeneric(outer, outer_image, k, cv::noArray(), rvecs, tvecs, false,
                        cv::SOLVEPNP_IPPE_SQUARE);
  } catch (const cv::Exception&) {
    rvecs.clear();
  }
  const Reprojection reprojection(object, image, k);
  std::vector<PoseFit> fits;
  for (size_t i = 0; i < rvecs.size(); ++i) {
    const cv::Vec3d rvec(rvecs[i].ptr<double>()), tvec(tvecs[i].ptr<double>());
    if (!Finite(rvec) || !Finite(tvec)) continue;
    PoseFit fit;
    cv::Rodrigues(rvec, fit.rotation);
    fit.translation = tvec;
    reprojection.Refine(&fit);
    if (std::isfinite(fit.rms_px)) fits.push_back(fit);
  }
  // And the pose the outer square's homography gives (the camera matrix
  // taken out, its first two columns the rotation's): IPPE returns the
  // identity, a reflection of the truth, for an exactly symmetric frontal
  // square.
  {
    std::vector<cv::Point2f> plane, seen;
    for (int i = 0; i < 4; ++i) {
      plane.emplace_back(static_cast<float>(outer[i].x), static_cast<float>(outer[i].y));
      seen.emplace_back(static_cast<float>(outer_image[i].x), static_cast<float>(outer_image[i].y));
    }
    const cv::Matx33d m = k.inv() * cv::Matx33d(cv::getPerspectiveTransform(plane, seen));
    const cv::Vec3d c0(m(0, 0), m(1, 0), m(2, 0)), c1(m(0, 1), m(1, 1), m(2, 1)),
        c2(m(0, 2), m(1, 2), m(2, 2));
    double scale = 2.0 / (cv::norm(c0) + cv::norm(c1));
    if (c2[2] * scale < 0) scale = -scale;  // The tag in front of the camera.
    const cv::Vec3d r0 = scale * c0, r1 = scale * c1, r2 = r0.cross(r1);
    PoseFit fit;
    fit.rotation =
        Orthonormal(cv::Matx33d(r0[0], r1[0], r2[0], r0[1], r1[1], r2[1], r0[2], r1[2], r2[2]));
    fit.translation = scale * c2;
    if (std::isfinite(scale) && Finite(fit.translation)) {
      reprojection.Refine(&fit);
      if (std::isfinite(fit.rms_px)) fits.push_back(fit);
    }
  }
  std::sort(fits.begin(), fits.end(),
            [](const PoseFit& a, const PoseFit& b) { return a.rms_px < b.rms_px; });
  return fits;
}

cv::Matx33d Orthonormal(const cv::Matx33d& m) {
  cv::Mat w, u, vt;
  cv::SVD::compute(cv::Mat(m), w, u, vt);
  cv::Matx33d r = cv::Matx33d(cv::Mat(u * vt));
  if (cv::determinant(r) < 0) {
    cv::Mat flip = cv::Mat::eye(3, 3, CV_64F);
    flip.at<double>(2, 2) = -1;
    r = cv::Matx33d(cv::Mat(u * flip * vt));
  }
  return r;
}

double AngleBetween(const cv::Matx33d& a, const cv::Matx33d& b) {
  cv::Vec3d apart;
  cv::Rodrigues(Orthonormal(a.t() * b), apart);
  return cv::norm(apart);
}

bool Finite(const cv::Vec3d& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

const PoseFit* Rival(const std::vector<PoseFit>& fits) {
  // Solutions refined into one (a frontal view: the planar solutions are its
  // mirror tilts) leave nothing ambiguous.
  for (size_t i = 1; i < fits.size(); ++i) {
    if (AngleBetween(fits[0].rotation, fits[i].rotation) > kSameSolutionRadians &&
        fits[i].rms_px > 0)
      return &fits[i];
  }
  return nullptr;
}

double Ambiguity(const std::vector<PoseFit>& fits) {
  const PoseFit* rival = Rival(fits);
  return rival ? fits[0].rms_px / rival->rms_px : 0.0;
}

}  // namespace chromatag::internal
