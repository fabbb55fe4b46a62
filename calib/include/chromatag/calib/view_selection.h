// Choosing calibration views from a video or a live camera, as ROS's
// camera_calibration and Kalibr do: a frame is worth keeping when it shows
// enough of the board and either puts corners where no kept view has them
// or sees the board from a pose unlike every kept view's (position in the
// image, size, tilt about either axis), up to a cap.
#ifndef CHROMATAG_CALIB_VIEW_SELECTION_H_
#define CHROMATAG_CALIB_VIEW_SELECTION_H_

#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/detector/board.h"
#include "chromatag/detector/detection.h"

namespace chromatag {

struct ViewSelectionOptions {
  int max_views = 40;  // The cap; [3, 1000].
  int min_tags = 2;    // Board tags a frame must show.
  // A frame is kept when its pose is at least this far from every kept
  // view's (the sum of differences of the board's centre in the image, as
  // shares of its width and height, its apparent size, and the sines of its
  // tilt about x and y) or when at least `min_new_cells` of the image's 8 x 6
  // cells that it covers are covered by no kept view.
  double min_pose_distance = 0.2;
  int min_new_cells = 3;

  bool IsValid(std::string* error) const;
};

// Where and how the board appears in one frame.
struct ViewPose {
  double centre_x = 0, centre_y = 0;  // Of the board's corners, shares of the image.
  double size = 0;                    // sqrt(area of their hull / the image's).
  double tilt_x = 0, tilt_y = 0;      // The board normal's x and y in the camera.
  std::array<bool, 48> cells{};       // The 8 x 6 cells holding a corner.
  int corners = 0;

  double DistanceTo(const ViewPose& other) const;
};

struct ViewDecision {
  bool keep = false;
  std::string why;  // Why kept or not, for the user.
};

// Offer frames one at a time (a live camera) or all of them and take the
// best (a video file).
class ViewSelector {
 public:
  ViewSelector(const Board& board, cv::Size image_size, const ViewSelectionOptions& options);

  // Where the board is in a frame; false when fewer than min_tags board
  // tags are seen or the board's pose cannot be found (*why says which).
  // One selector is for one image size.
  bool Describe(const std::vector<Detection>& detections, ViewPose* pose, std::string* why) const;

  // Live: decides now, against the views kept so far.
  ViewDecision Offer(const std::vector<Detection>& detections);
  bool full() const { return static_cast<int>(kept_.size()) >= options_.max_views; }
  int kept() const { return static_cast<int>(kept_.size()); }

  // Offline: from every candidate's pose (Describe), the indices to keep,
  // chosen greedily against the views kept so far: each time the one that
  // adds most (new cells of the image, then distance to the kept poses; the
  // most corners for the very first) until none adds enough or the cap is
  // reached. The chosen join the kept views. `why` gets a reason for every
  // candidate, kept or not.
  std::vector<size_t> Choose(const std::vector<ViewPose>& candidates,
                             std::vector<std::string>* why);

 private:
  // New cells and the distance to the nearest kept pose (and its index).
  void Compare(const ViewPose& pose, const std::vector<const ViewPose*>& kept, int* new_cells,
               double* distance, int* nearest) const;

  const Board& board_;
  cv::Size image_size_;
  ViewSelectionOptions options_;
  std::vector<ViewPose> kept_;
};

}  // namespace chromatag

#endif  // CHROMATAG_CALIB_VIEW_SELECTION_H_
