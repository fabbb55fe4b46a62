// 2. InitialScan: scans left, right, up and down from the seed to the
// red/green border, re-centres until the centre converges, then scans on
// through all three borders. Seeds the candidate's polygons. Internal to the
// detector.
#ifndef CHROMATAG_DETECTOR_SRC_INITIAL_SCAN_H_
#define CHROMATAG_DETECTOR_SRC_INITIAL_SCAN_H_

#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "candidate.h"
#include "chromatag/detector/detection.h"
#include "chromatag/detector/options.h"
#include "find_adiff.h"
#include "image_view.h"
#include "scan_rings.h"

namespace chromatag::internal {

// The red/green border polygon of a red region InitialScan rejected after at
// least one centring pass (eight points, star-shaped around its centre).
struct RejectedRegion {
  std::array<cv::Point2f, 8> border;
  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;
  // Every seed is tested against every region rejected so far in the frame
  // (hundreds on busy frames): the box test inline, the polygon only inside.
  bool Contains(cv::Point2f p) const {
    return p.x >= min_x && p.x <= max_x && p.y >= min_y && p.y <= max_y && BorderContains(p);
  }
  bool BorderContains(cv::Point2f p) const;  // Even-odd rule over `border`.
  // The region of a centring pass's red/green border points, grown a little
  // about its centre: the seeds of later rows lie on the region's left edge,
  // where the polygon's sides cut inside.
  static RejectedRegion Around(const std::array<cv::Point2f, 8>& red_border);
  // Seeds that may still start inside the region before it drops them: a
  // red the later stages lost (BuildPolygon to Decode, and GrowRegion) is
  // tried again from seeds of later rows, which start from another part of
  // its border and may find the tag the first lost. The reds InitialScan
  // itself rejects have none: tag-free frames have dozens of those.
  int retries = 0;
};

// A candidate the later stages lost gets this many more seeds on its red:
// as many tags as with no limit, 9 more on the camera set's 8,000 frames
// with the defaults (10 with the calibrated `iccv17-faded` config, a 101 px
// tag among them) and 10 more on the classic set's 10,000, while a tag that
// cannot be read (a swapped print) costs at most five passes. Tag-free
// frames have almost no such candidates.
inline constexpr int kLostRedRetries = 4;

// Whether `seed` lies in a region rejected so far (none with `rejected`
// null) that has no retries left; a region that has some spends one, and
// *retry says so.
bool InRejectedRegion(std::vector<RejectedRegion>* rejected, cv::Point2f seed,
                      bool* retry = nullptr);

// Drops the regions that end above row y. Rows are sampled top to bottom,
// so no later seed can lie in one, and a busy frame's seeds (thousands in
// the chroma noise of a dark one) no longer each test every region the
// frame has rejected.
void ForgetRegionsAbove(float y, std::vector<RejectedRegion>* regions);

// InitialScan from a seed of the given kind (FindADiff). With `rejected`
// (the frame's regions rejected so far), a seed inside one of them is
// dropped at once, and a region rejected after a centring pass is added.
bool InitialScan(const ImageView& image, const DetectorOptions& options, cv::Point seed, Seed kind,
                 RingScanBuffers* buffers, Candidate* candidate,
                 std::vector<RejectedRegion>* rejected, RejectReason* why);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_INITIAL_SCAN_H_
