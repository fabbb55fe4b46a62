#include "chromatag/detector/board.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>

#include <opencv2/calib3d.hpp>

#include "chromatag/detector/camera.h"
#include "chromatag/detector/corner_bend.h"

#include "pose_fit.h"

namespace chromatag {
namespace {

using internal::PoseFit;

// A tag agrees with a board pose when the rms reprojection error of its
// twelve corners is below this share of its black square's side in pixels,
// or below kMinInlierPx. A tag put in another tag's place (a misread ID) is
// a whole side or more off; a pose proposed by one small tag and carried
// across the board is off by far less.
constexpr double kInlierShareOfSide = 0.25;
constexpr double kMinInlierPx = 2.0;
// Refit rounds until the tags that agree stop changing.
constexpr int kMaxRounds = 5;
// Proposals closer than this to the refined pose (radians) are the same
// solution seen through one tag's noise, not its rival.
constexpr double kRivalRadians = 2.0 * CV_PI / 180.0;

// A detection of a board tag.
struct Match {
  int detection = 0;               // Index into the detections.
  int tag = 0;                     // Index into Board::tags.
  std::vector<cv::Point3d> local;  // Its twelve ring corners in the tag frame...
  std::vector<cv::Point3d> board;  // ...and in the board frame.
  std::vector<cv::Point2d> image;  // Where they were seen, undistorted.
  double threshold_px = kMinInlierPx;
};

struct Proposal {
  PoseFit pose;  // camera_from_board.
  double cost = 0.0;
};

double MatchRms(const Match& match, const PoseFit& pose, const cv::Matx33d& k) {
  return internal::Reprojection(match.board, match.image, k).Rms(pose.rotation, pose.translation);
}

// Each match's error under `pose` over its threshold, squared and capped at
// 1 (an MSAC cost): the pose most tags agree with, closely, costs least.
double Cost(const std::vector<Match>& matches, const PoseFit& pose, const cv::Matx33d& k) {
  double cost = 0.0;
  for (const Match& match : matches) {
    const double e = MatchRms(match, pose, k) / match.threshold_px;
    cost += std::isfinite(e) ? std::min(e * e, 1.0) : 1.0;
  }
  return cost;
}

std::vector<int> Agreeing(const std::vector<Match>& matches, const PoseFit& pose,
                          const cv::Matx33d& k) {
  std::vector<int> agreeing;
  for (size_t i = 0; i < matches.size(); ++i) {
    if (MatchRms(matches[i], pose, k) < matches[i].threshold_px)
      agreeing.push_back(static_cast<int>(i));
  }
  return agreeing;
}

// Refits `pose` on the matches that agree with it until they stop changing;
// returns them (empty when none agrees with the start).
std::vector<int> Refit(const std::vector<Match>& matches, const cv::Matx33d& k, PoseFit* pose) {
  std::vector<int> agreeing = Agreeing(matches, *pose, k);
  for (int round = 0; round < kMaxRounds && !agreeing.empty(); ++round) {
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (int i : agreeing) {
      object.insert(object.end(), matches[i].board.begin(), matches[i].board.end());
      image.insert(image.end(), matches[i].image.begin(), matches[i].image.end());
    }
    PoseFit refined = *pose;
    internal::Reprojection(object, image, k).Refine(&refined);
    if (!std::isfinite(refined.rms_px)) break;
    *pose = refined;
    // The pose and its rms belong to `agreeing`; the next round refits only
    // when the tags that agree with the new pose differ.
    std::vector<int> next = Agreeing(matches, *pose, k);
    if (next == agreeing || next.empty() || round + 1 == kMaxRounds) break;
    agreeing = std::move(next);
  }
  return agreeing;
}

}  // namespace

std::vector<cv::Point3d> BoardTagCorners(const BoardTag& tag, const TagFamily& family) {
  std::vector<cv::Point3d> corners = internal::TagRingCorners(family, tag.size);
  for (cv::Point3d& p : corners) {
    const cv::Vec3d q = tag.rotation * cv::Vec3d(p.x, p.y, p.z) + tag.translation;
    p = {q[0], q[1], q[2]};
  }
  return corners;
}

bool Board::IsValid(std::string* error) const {
  auto fail = [&](size_t i, const std::string& what) {
    if (error) {
      *error = "board tag " + std::to_string(i + 1) + " (" + tags[i].family + " ID " +
               std::to_string(tags[i].id) + "): " + what;
    }
    return false;
  };
  if (tags.empty()) {
    if (error) *error = "a board needs at least one tag";
    return false;
  }
  std::set<std::pair<std::string, int>> seen;
  for (size_t i = 0; i < tags.size(); ++i) {
    const BoardTag& tag = tags[i];
    const auto& names = TagFamily::Names();
    if (std::find(names.begin(), names.end(), tag.family) == names.end())
      return fail(i, "unknown family (16h5 or 36h11)");
    std::string why;
    if (!TagFamily::Load(tag.family)->IsValidId(tag.id, &why)) return fail(i, why);
    if (!seen.insert({tag.family, tag.id}).second) return fail(i, "is on the board twice");
    if (!(tag.size >= kMinBoardTagSize && tag.size <= kMaxBoardTagSize)) {
      char why[128];
      std::snprintf(why, sizeof(why), "the size %g m is out of range (%g to %g m)", tag.size,
                    kMinBoardTagSize, kMaxBoardTagSize);
      return fail(i, why);
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (!(std::fabs(tag.translation[axis]) <= kMaxBoardReach)) {
        char why[128];
        std::snprintf(why, sizeof(why),
                      "the position's %c, %g m, is out of range (at most %g m from the board's "
                      "origin)",
                      "xyz"[axis], tag.translation[axis], kMaxBoardReach);
        return fail(i, why);
      }
    }
    const cv::Matx33d rtr = tag.rotation.t() * tag.rotation;
    double off = 0.0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) off = std::max(off, std::fabs(rtr(r, c) - (r == c ? 1.0 : 0.0)));
    if (!(off < 1e-6) || !(cv::determinant(tag.rotation) > 0))
      return fail(i, "the orientation is not a rotation");
  }
  return true;
}

int Board::Find(const std::string& family, int id) const {
  for (size_t i = 0; i < tags.size(); ++i) {
    if (tags[i].id == id && tags[i].family == family) return static_cast<int>(i);
  }
  return -1;
}

namespace {

// The detections of the board's tags, each with its corners in the tag's,
// the board's and the (undistorted) image's frame.
std::vector<Match> MatchBoardTags(const std::vector<Detection>& detections, const Board& board,
                                  const CameraIntrinsics& camera) {
  std::vector<Match> matches;
  for (size_t d = 0; d < detections.size(); ++d) {
    const Detection& detection = detections[d];
    if (detection.family == nullptr) continue;
    const int index = board.Find(detection.family->name(), detection.id);
    if (index < 0) continue;
    const BoardTag& tag = board.tags[index];
    Match match;
    match.detection = static_cast<int>(d);
    match.tag = index;
    if (!internal::UndistortedRingCorners(detection, camera, &match.image, nullptr)) continue;
    match.local = internal::TagRingCorners(*detection.family, tag.size);
    for (const cv::Point3d& p : match.local) {
      const cv::Vec3d q = tag.rotation * cv::Vec3d(p.x, p.y, p.z) + tag.translation;
      match.board.emplace_back(q[0], q[1], q[2]);
    }
    double side = 0.0;
    for (int i = 0; i < 4; ++i) side += 0.25 * cv::norm(match.image[(i + 1) % 4] - match.image[i]);
    match.threshold_px = std::max(kMinInlierPx, kInlierShareOfSide * side);
    matches.push_back(std::move(match));
  }
  return matches;
}

// Every tag's distinct planar solutions, carried to the board frame, best
// (cheapest) first. Stable: among equally good proposals the first
// detection's wins, run after run.
std::vector<Proposal> ProposePoses(const std::vector<Match>& matches, const Board& board,
                                   const cv::Matx33d& k) {
  std::vector<Proposal> proposals;
  for (const Match& match : matches) {
    const BoardTag& tag = board.tags[match.tag];
    std::vector<PoseFit> seen;
    for (const PoseFit& fit : internal::TagPoseFits(match.local, match.image, k)) {
      bool distinct = true;
      for (const PoseFit& s : seen)
        distinct &=
            internal::AngleBetween(s.rotation, fit.rotation) > internal::kSameSolutionRadians;
      if (!distinct) continue;
      seen.push_back(fit);
      Proposal proposal;
      proposal.pose.rotation = fit.rotation * tag.rotation.t();
      proposal.pose.translation = fit.translation - proposal.pose.rotation * tag.translation;
      proposal.cost = Cost(matches, proposal.pose, k);
      proposals.push_back(proposal);
    }
  }
  std::stable_sort(proposals.begin(), proposals.end(),
                   [](const Proposal& a, const Proposal& b) { return a.cost < b.cost; });
  return proposals;
}

// The best proposal refitted, then the best one whose rotation differs from
// where the first settled (the other planar solution): the pose and its
// rival, each with the matches that agree with it.
void PoseAndRival(const std::vector<Proposal>& proposals, const std::vector<Match>& matches,
                  const cv::Matx33d& k, std::vector<PoseFit>* fits,
                  std::vector<std::vector<int>>* agreeing) {
  for (const Proposal& proposal : proposals) {
    if (!fits->empty() &&
        internal::AngleBetween((*fits)[0].rotation, proposal.pose.rotation) < kRivalRadians)
      continue;
    PoseFit fit = proposal.pose;
    std::vector<int> used = Refit(matches, k, &fit);
    if (used.empty() || !std::isfinite(fit.rms_px)) continue;
    fits->push_back(fit);
    agreeing->push_back(std::move(used));
    if (fits->size() == 2) break;
  }
}

// The tags the pose used and the detections that disagree with it.
void SetTagsUsed(const std::vector<Match>& matches, const std::vector<int>& agreeing,
                 BoardPose* pose) {
  std::set<int> used;
  std::vector<bool> agrees(matches.size(), false);
  for (int i : agreeing) {
    used.insert(matches[i].tag);
    agrees[i] = true;
  }
  pose->tags_used.assign(used.begin(), used.end());
  pose->detections_rejected.clear();
  for (size_t i = 0; i < matches.size(); ++i)
    if (!agrees[i]) pose->detections_rejected.push_back(matches[i].detection);
}

// The covariance of fits[best] from the corners of the tags that agree
// with it; the other solution is its rival when as many tags agree with it.
cv::Matx66d BoardCovariance(const std::vector<Detection>& detections,
                            const CameraIntrinsics& camera, const std::vector<Match>& matches,
                            const std::vector<std::vector<int>>& agreeing,
                            const std::vector<PoseFit>& fits, size_t best, const cv::Matx33d& k) {
  std::vector<internal::CornerNoise> noise;
  noise.reserve(agreeing[best].size());
  for (int i : agreeing[best]) {
    internal::CornerNoise tag;
    if (internal::TagCornerNoise(detections[matches[i].detection], camera, matches[i].board, &tag))
      noise.push_back(std::move(tag));
  }
  std::vector<const internal::CornerNoise*> tags;
  for (const internal::CornerNoise& tag : noise) tags.push_back(&tag);
  const PoseFit* rival = nullptr;
  if (fits.size() == 2 && agreeing[1 - best].size() == agreeing[best].size())
    rival = &fits[1 - best];
  return internal::PoseCovariance(tags, fits[best], rival, k);
}

// EstimateBoardPose on the detections' corners as they are; the covariance
// only `with_covariance`.
bool FitBoardPose(const std::vector<Detection>& detections, const Board& board,
                  const CameraIntrinsics& camera, bool with_covariance, BoardPose* pose,
                  std::string* error) {
  const cv::Matx33d k = CameraMatrix(camera);
  const std::vector<Match> matches = MatchBoardTags(detections, board, camera);
  if (matches.empty()) {
    if (error) {
      *error = "none of the board's " + std::to_string(board.tags.size()) +
               " tags is among the detections";
    }
    return false;
  }
  std::vector<PoseFit> fits;
  std::vector<std::vector<int>> agreeing;
  PoseAndRival(ProposePoses(matches, board, k), matches, k, &fits, &agreeing);
  if (fits.empty()) {
    if (error) *error = "no pose puts the board's tags in front of the camera";
    return false;
  }
  // The rival wins if it explains as many tags better.
  size_t best = 0;
  if (fits.size() == 2 && agreeing[1].size() >= agreeing[0].size() &&
      (agreeing[1].size() > agreeing[0].size() || fits[1].rms_px < fits[0].rms_px))
    best = 1;
  const PoseFit& fit = fits[best];
  cv::Vec3d rvec;
  cv::Rodrigues(internal::Orthonormal(fit.rotation), rvec);
  if (!internal::Finite(rvec) || !internal::Finite(fit.translation)) {
    if (error) *error = "the board's pose is not finite";
    return false;
  }
  pose->rvec = rvec;
  pose->tvec = fit.translation;
  pose->rms_error_px = fit.rms_px;
  pose->ambiguity = 0.0;
  if (fits.size() == 2) {
    const PoseFit& other = fits[1 - best];
    if (internal::AngleBetween(fit.rotation, other.rotation) > internal::kSameSolutionRadians &&
        other.rms_px > 0 && agreeing[1 - best].size() == agreeing[best].size())
      pose->ambiguity = std::min(1.0, fit.rms_px / other.rms_px);
  }
  SetTagsUsed(matches, agreeing[best], pose);
  if (with_covariance)
    pose->covariance = BoardCovariance(detections, camera, matches, agreeing, fits, best, k);
  return true;
}

}  // namespace

bool EstimateBoardPose(const std::vector<Detection>& detections, const Board& board,
                       const CameraIntrinsics& camera, BoardPose* pose, std::string* error) {
  if (!camera.IsValid(error) || !board.IsValid(error)) return false;
  const bool distorted = HasDistortion(camera);
  if (!FitBoardPose(detections, board, camera, !distorted, pose, error)) return false;
  if (!distorted) return true;
  // The lens bends the tags' sides (corner_bend.h): the pose once more, from
  // every board tag's corners straightened under the first.
  std::vector<Detection> straight = detections;
  for (Detection& d : straight) {
    const int index = d.family ? board.Find(d.family->name(), d.id) : -1;
    if (index < 0) continue;
    d = Straightened(d, CornerBend(camera, BoardTagCorners(board.tags[index], *d.family),
                                   pose->rvec, pose->tvec));
  }
  if (FitBoardPose(straight, board, camera, true, pose, nullptr)) return true;
  // Straightened corners that fit no pose: the first, with its covariance.
  return FitBoardPose(detections, board, camera, true, pose, error);
}

}  // namespace chromatag
