#include "chromatag/calib/view_selection.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace chromatag {
namespace {

constexpr int kCellsX = 8, kCellsY = 6;

std::string Format(const char* format, double a, double b = 0.0) {
  char text[160];
  std::snprintf(text, sizeof text, format, a, b);
  return text;
}

}  // namespace

bool ViewSelectionOptions::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (max_views < 3 || max_views > 1000)
    return fail("the most views to keep must be in [3, 1000], got " + std::to_string(max_views));
  if (min_tags < 1) return fail("a view needs at least 1 board tag");
  if (!(min_pose_distance > 0) || min_new_cells < 1)
    return fail("min_pose_distance must be > 0 and min_new_cells at least 1");
  return true;
}

double ViewPose::DistanceTo(const ViewPose& o) const {
  return std::abs(centre_x - o.centre_x) + std::abs(centre_y - o.centre_y) +
         std::abs(size - o.size) + std::abs(tilt_x - o.tilt_x) + std::abs(tilt_y - o.tilt_y);
}

ViewSelector::ViewSelector(const Board& board, cv::Size image_size,
                           const ViewSelectionOptions& options)
    : board_(board), image_size_(image_size), options_(options) {}

bool ViewSelector::Describe(const std::vector<Detection>& detections, ViewPose* pose,
                            std::string* why) const {
  std::vector<cv::Point2f> corners;
  int tags = 0;
  for (const Detection& d : detections) {
    if (d.family == nullptr || board_.Find(d.family->name(), d.id) < 0) continue;
    // Detections handed in by a program may hold anything.
    bool finite = true;
    for (const auto* ring : {&d.corners, &d.green_corners, &d.red_corners})
      for (const cv::Point2d& p : *ring) finite &= std::isfinite(p.x) && std::isfinite(p.y);
    if (!finite) continue;
    ++tags;
    for (const auto* ring : {&d.corners, &d.green_corners, &d.red_corners})
      for (const cv::Point2d& p : *ring) corners.emplace_back(p);
  }
  if (tags < options_.min_tags) {
    *why = std::to_string(tags) + " board tag(s) seen (needs " + std::to_string(options_.min_tags) +
           ")";
    return false;
  }
  // The tilt needs a camera; the real one is what is being calibrated. A
  // typical lens (a 64-degree field of view across the width) tells the
  // board's tilt well enough to tell poses apart.
  CameraIntrinsics nominal;
  nominal.fx = nominal.fy = 0.8 * image_size_.width;
  nominal.cx = 0.5 * image_size_.width;
  nominal.cy = 0.5 * image_size_.height;
  BoardPose board_pose;
  if (!EstimateBoardPose(detections, board_, nominal, &board_pose)) {
    *why = "the board's pose could not be found";
    return false;
  }
  cv::Matx33d r;
  cv::Rodrigues(board_pose.rvec, r);
  *pose = ViewPose();
  pose->tilt_x = r(0, 2);
  pose->tilt_y = r(1, 2);
  cv::Point2d sum(0, 0);
  for (const cv::Point2f& p : corners) {
    sum += cv::Point2d(p);
    // Clamped before the conversion: a corner far outside the image (or a
    // float's infinity) is no int.
    const int cx = static_cast<int>(
        std::clamp(static_cast<double>(p.x) * kCellsX / image_size_.width, 0.0, kCellsX - 1.0));
    const int cy = static_cast<int>(
        std::clamp(static_cast<double>(p.y) * kCellsY / image_size_.height, 0.0, kCellsY - 1.0));
    pose->cells[cy * kCellsX + cx] = true;
  }
  pose->corners = static_cast<int>(corners.size());
  pose->centre_x = sum.x / corners.size() / image_size_.width;
  pose->centre_y = sum.y / corners.size() / image_size_.height;
  std::vector<cv::Point2f> hull;
  cv::convexHull(corners, hull);
  pose->size = std::sqrt(cv::contourArea(hull) / image_size_.area());
  return true;
}

void ViewSelector::Compare(const ViewPose& pose, const std::vector<const ViewPose*>& kept,
                           int* new_cells, double* distance, int* nearest) const {
  *new_cells = 0;
  for (size_t c = 0; c < pose.cells.size(); ++c) {
    if (!pose.cells[c]) continue;
    bool seen = false;
    for (const ViewPose* k : kept) seen |= k->cells[c];
    *new_cells += seen ? 0 : 1;
  }
  *distance = std::numeric_limits<double>::infinity();
  *nearest = -1;
  for (size_t i = 0; i < kept.size(); ++i) {
    const double d = pose.DistanceTo(*kept[i]);
    if (d < *distance) {
      *distance = d;
      *nearest = static_cast<int>(i);
    }
  }
}

ViewDecision ViewSelector::Offer(const std::vector<Detection>& detections) {
  ViewDecision decision;
  if (full()) {
    decision.why = "the cap of " + std::to_string(options_.max_views) + " views is reached";
    return decision;
  }
  ViewPose pose;
  if (!Describe(detections, &pose, &decision.why)) return decision;
  std::vector<const ViewPose*> kept;
  for (const ViewPose& k : kept_) kept.push_back(&k);
  int new_cells = 0, nearest = -1;
  double distance = 0;
  Compare(pose, kept, &new_cells, &distance, &nearest);
  if (kept.empty()) {
    decision.why = "the first view";
  } else if (new_cells >= options_.min_new_cells) {
    decision.why = Format("covers %.0f new cells of the image", new_cells);
  } else if (distance >= options_.min_pose_distance) {
    decision.why = Format("a new pose (%.2f from the nearest kept view)", distance);
  } else {
    decision.why = Format("like kept view %.0f (pose %.2f apart)", nearest + 1, distance);
    return decision;
  }
  decision.keep = true;
  kept_.push_back(pose);
  return decision;
}

namespace {

// The image cells a view covers, a bit per cell.
uint64_t CellBits(const ViewPose& pose) {
  uint64_t b = 0;
  for (size_t c = 0; c < pose.cells.size(); ++c) b |= pose.cells[c] ? uint64_t{1} << c : 0;
  return b;
}

}  // namespace

std::vector<size_t> ViewSelector::Choose(const std::vector<ViewPose>& candidates,
                                         std::vector<std::string>* why) {
  why->assign(candidates.size(), "");
  // Each candidate's new cells (a bit per cell) and distance to the nearest
  // kept pose, brought up to date as views are kept.
  const auto bits = CellBits;
  uint64_t covered = 0;
  for (const ViewPose& k : kept_) covered |= bits(k);
  std::vector<uint64_t> cells(candidates.size());
  std::vector<double> distance(candidates.size(), std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < candidates.size(); ++i) {
    cells[i] = bits(candidates[i]);
    for (const ViewPose& k : kept_)
      distance[i] = std::min(distance[i], candidates[i].DistanceTo(k));
  }
  const auto new_cells = [&](size_t i) { return __builtin_popcountll(cells[i] & ~covered); };
  const auto adds = [&](size_t i) {
    return kept_.empty() || new_cells(i) >= options_.min_new_cells ||
           distance[i] >= options_.min_pose_distance;
  };
  std::vector<size_t> chosen;
  std::vector<bool> taken(candidates.size(), false);
  while (!full()) {
    // Most new cells first (when enough to count), then the most distant
    // pose; the very first view: the most corners.
    int best = -1, best_cells = -1;
    double best_score = -1;
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (taken[i] || !adds(i)) continue;
      const int n = !kept_.empty() && new_cells(i) >= options_.min_new_cells ? new_cells(i) : 0;
      const double score = kept_.empty() ? candidates[i].corners : distance[i];
      if (n > best_cells || (n == best_cells && score > best_score)) {
        best = static_cast<int>(i);
        best_cells = n;
        best_score = score;
      }
    }
    if (best < 0) break;
    const size_t b = static_cast<size_t>(best);
    (*why)[b] = kept_.empty() ? std::string("the first view, with the most corners")
                : new_cells(b) >= options_.min_new_cells
                    ? Format("covers %.0f new cells of the image", new_cells(b))
                    : Format("a new pose (%.2f from the nearest kept view)", distance[b]);
    taken[b] = true;
    chosen.push_back(b);
    kept_.push_back(candidates[b]);
    covered |= cells[b];
    for (size_t i = 0; i < candidates.size(); ++i)
      distance[i] = std::min(distance[i], candidates[i].DistanceTo(candidates[b]));
  }
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (taken[i]) continue;
    (*why)[i] = adds(i) ? "the cap of " + std::to_string(options_.max_views) + " views is reached"
                        : Format("like a kept view (pose %.2f apart, %.0f new cells)", distance[i],
                                 new_cells(i));
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

}  // namespace chromatag
