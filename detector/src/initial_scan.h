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

// The red/green border polygon of a red region rejected in this frame after
// at least one centring pass, by InitialScan or by a later stage (eight
// points, star-shaped around its centre). Red things that are not tags span
// many of FindADiff's rows, and each row seeds them again.
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
  // red that passed InitialScan and was then lost (BuildPolygon to Decode,
  // then GrowRegion) is tried again by the next seeds inside it, which
  // start from other points of its border and may find the tag the first
  // lost. So has a red InitialScan rejects after its centre converged, for
  // its final ring scans or their proportions (GrowRegion then tries it);
  // the other reds it rejects have none: tag-free frames have dozens of
  // those.
  int retries = 0;
};

// A candidate the later stages lost gets this many more seeds on its red:
// on the camera set as many tags as with no limit, while a tag that cannot
// be read costs at most five passes (one if a read fits a swapped print).
// Tag-free frames have almost no such candidates.
inline constexpr int kLostRedRetries = 4;
// A red whose centre converged and whose final ring scans (their rings, or
// the whites that settle its light) or their proportions then failed gets
// this many more seeds. Such a red is grown (GrowRegion); a seed from
// another point of its border starts the scans and the growing again from
// another centre and border, which on small and steep tags often finds the
// square the first missed. On the camera
// set 18 tags more (15 of them under 30 px or over 60 degrees), none lost;
// tag-free frames grow 0.23 more reds each (8 %). A red any read refused as
// fitting a swapped print keeps no retries (Candidate::fits_swapped_print:
// each would be another chance for the swapped print to pass as another
// ID).
inline constexpr int kCentredRedRetries = 4;

// What a seed's place among the frame's rejected regions allows.
enum class SeedAdmission {
  kFree,     // In no region: it starts.
  kRetry,    // In a region with retries left, and none without: it spends
             // one and starts.
  kDropped,  // In a region with no retries left.
};
// The admission of `seed` (kFree with `rejected` null); a kRetry spends one
// of its region's retries and, with `region`, says which (its index in
// `rejected`; *region is left as it is otherwise).
SeedAdmission AdmitSeed(std::vector<RejectedRegion>* rejected, cv::Point2f seed,
                        int* region = nullptr);

// Drops the regions that end above row y. Rows are sampled top to bottom,
// so no later seed can lie in one, and a busy frame's seeds (thousands in
// the chroma noise of a dark one) no longer each test every region the
// frame has rejected.
void ForgetRegionsAbove(float y, std::vector<RejectedRegion>* regions);

// InitialScan from a seed of the given kind (FindADiff). With `rejected`
// (the frame's regions rejected so far), a seed is admitted first
// (AdmitSeed: a dropped one fails at once, a retry sets Candidate::retry),
// and a region rejected after a centring pass is added unless the
// candidate is a retry or its colours passed only in its own light (with
// kCentredRedRetries if its centre converged and its final ring scans or
// their proportions failed); the region's index goes to Candidate::region
// when one is added.
bool InitialScan(const ImageView& image, const DetectorOptions& options, cv::Point seed, Seed kind,
                 RingScanBuffers* buffers, Candidate* candidate,
                 std::vector<RejectedRegion>* rejected, RejectReason* why);

}  // namespace chromatag::internal

#endif  // CHROMATAG_DETECTOR_SRC_INITIAL_SCAN_H_
