// Stage 2, InitialScan (paper section 4, Figure 6a-c).
#include "initial_scan.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "candidate.h"
#include "geometry.h"
#include "scan_rings.h"

namespace chromatag::internal {
namespace {

constexpr int kMaxCentreIterations = 8;
// The centre counts as settled when a pass moves it less than this on each
// axis. The final scans start from it and the outer quad's corners are found
// on their own edges, so a centre within a few pixels serves; 0.75 px took a
// pass or two more on most tags (3.3 passes of eight scans on average). On the
// camera set's first 1,500 frames 2.5 px found 813 tags instead of 808 (the
// classic set's 924 instead of 921), every ID right, the outer corners'
// median error 0.85 px as before.
constexpr float kConvergedPx = 2.5f;
// The axis directions (kScanDirections) whose rings are checked after the
// first centring pass, to drop red things that are not tags early: right and
// down, which dropped 2,246 of the 2,645 candidates the four axes dropped
// there on those frames. The final scans check all four.
constexpr int kEarlyRingDirections[] = {0, 2};

// The order of CentringPass's scans. They are independent, so the order
// changes only how soon a candidate that fails is dropped: up first, since
// FindADiff meets a red region on the first sampled row that crosses it, near
// its top, so the upward scan is short and reaches what borders the red
// there (a tag's green, something else for most red things); then the other
// axes, then the diagonals. On the camera set's first 600 frames: 20 % fewer
// pixels walked and InitialScan 4.7 % faster than in index order, the same
// detections.
constexpr int kCentringOrder[8] = {6, 2, 4, 0, 5, 7, 3, 1};
// A red one pixel across between two opposite scans of a centring pass (the
// borders half a pixel either side of the centre) is dropped: such
// candidates are mostly the chroma noise of a dark frame, where demosaicing
// and sensor noise put single pixels past ADiffThresh (up to 3,000 seeds on
// one dark frame of the camera set), now dropped after two to six scans
// instead of a pass of eight: an eighth less time on the camera set's
// tag-free frames. The cost: a tag so small that FindADiff's only seed on it
// is a corner pixel of its red. On the camera set's 8,000 frames this lost 4
// tags and found 1 (all under 20 px); on the classic set's 10,000 it lost 7
// of 15-18 px.
constexpr float kMinRedSpanPx = 1.5f;
// Pixels past a red/green run searched for the green's full a* drop.
constexpr int kGreenLookAhead = 6;
// A red paler than the drop into green that CentringPass asks for needs a
// drop of this many times its own a* (GreenPastRed).
constexpr float kMinDropOverRed = 1.2f;
// With DetectorOptions::cast_seeds, the palest seed InitialScan starts from,
// in a*: a cast and dim light take a faded print's red to a* 10; the red's
// a* in the candidate's own light (kMinTagRedA) is checked once the final
// scans have found its white.
constexpr float kMinSeedRedA = 6.f;
// Pixels beyond where the red/green border is expected that a probe of the
// candidate's own light (ColoursInProbeLight) looks for it.
constexpr int kProbeSlack = 6;
// A run past the red threshold whose lowest a* stays within this many
// thresholds of ReferenceRed is a dip inside the red, not its border; a scan
// goes past at most kMaxRedDips of them (CentringPass).
constexpr float kRedDipDepth = 2.f;
constexpr int kMaxRedDips = 4;
// The a* drop into a tag's green, as a fraction of ADiffThresh: the palettes'
// reds and greens are 58 or more apart; a fifth less allows for blur and casts.
constexpr float kMinGreenDropFraction = 0.8f;
// A seed on the red's blurred edge (a dim card through JPEG: a* 13 where the
// red's own is 21) sees too small a drop into a green that JPEG has paled.
// A scan whose drop from the seed's a* falls short, but is at least this
// fraction of the drop needed, is judged again from the red's peak a* in
// the scans made so far (sampled half way along each), and the colours are
// then checked in the tag's own light as for a pale red, the red where the
// peak was sampled (the seed's pale edge may be paler than a tag's red in
// that light too). On the camera set's first 8,000 frames this found one
// 88 px 36h11 tag at 0.3 of the light through JPEG 60 and lost none.
// Switched on and off frame by frame on 600 of its tag-free frames (a
// scratch build), the check cost about 1 % of the mean time (+0.9 and
// +1.4 % in two runs, within about as much noise). A run short of
// kRedDipDepth thresholds stays a dip inside the red.
constexpr float kPeakCheckDrop = 0.5f;
// Ring widths along one scan (RingProportionsFit): a tag's green and black
// rings are one cell each, its red half-width one (16h5) or two (36h11)
// cells; perspective along one line changes these ratios little. Each ring
// lies between kMinRingOverRed and kMaxRingOverRed times the red half-width
// (plus kRingSlackPx for blur on small tags), and black over green between
// kMinBlackOverGreen and kMaxBlackOverGreen (each with a pixel of slack).
constexpr float kMinRingOverRed = 0.2f;
constexpr float kMaxRingOverRed = 2.5f;
constexpr float kRingSlackPx = 2.f;
constexpr float kMinBlackOverGreen = 0.4f;
constexpr float kMaxBlackOverGreen = 2.5f;
// A rejected region is its red/green border grown about its centre by this
// share of each point's distance plus a margin in pixels: the seeds of later
// rows lie on the region's left edge, where the octagon's sides cut inside.
constexpr float kRejectedRegionGrowth = 0.15f;
constexpr float kRejectedRegionMarginPx = 2.f;

// Whether a* `deepest_a` past a red of a* `reference_red` counts as a tag's
// green by absolute measures: a drop of at least `min_drop`, to an a* below
// `max_green_a`.
bool GreenPastRed(float reference_red, float deepest_a, float min_drop, float max_green_a) {
  return reference_red - deepest_a >= min_drop && deepest_a < max_green_a;
}

// The same, allowing for what dim light and a cast do to a*'s steps: a drop
// from a red paler than `min_drop` of kMinDropOverRed times the red's own
// a* (a dim card's faded red under a green cast sits at a* 10, its green 20
// below). A candidate that passes only this test must show a tag's colours
// in its own light (ColoursInProbeLight) before its scans go on.
bool GreenPastRedInACast(float reference_red, float deepest_a, float min_drop, float max_green_a) {
  const float needed =
      std::min(min_drop, std::max(0.5f * min_drop, kMinDropOverRed * reference_red));
  return reference_red - deepest_a >= needed && deepest_a < max_green_a;
}

// Whether the red at `red_at` and the green of one ring scan from `centre`
// in `direction` (from `skip` steps out, finding the red/green border within
// `red_reach` steps of there: the caller knows about where it lies) are a
// tag's in the light of that scan's quiet zone (TagLight): the red's a* at
// least kMinTagRedA, the green's below DetectorOptions::max_green_a.
bool ColoursInProbeLight(const ImageView& image, const DetectorOptions& options, cv::Point2f centre,
                         cv::Point red_at, cv::Point2f direction, int skip, int red_reach,
                         float reference_red, RingScanBuffers* buffers) {
  const cv::Point2f start = centre + static_cast<float>(skip) * direction;
  RingHits hits;
  if (!ScanRings(image, options, start, direction, reference_red, buffers, &hits, red_reach))
    return false;
  TagLight light;
  light.AddWhite(image, hits.white_at);
  if (!light.Settle()) return false;
  return light.BalancedAt(image, red_at).a >= static_cast<float>(kMinTagRedA) &&
         light.BalancedAt(image, hits.green_at).a < static_cast<float>(options.max_green_a);
}

// CentringPass's scan along one direction: from step *k on, to the end of
// the first run of M pixels whose a* lies more than `red_thresh` below
// ReferenceRed. Leaves *k on the run's last pixel and *deepest_a at the run's
// lowest a*, followed a few pixels on where the run ends on a blurred slope.
// False (and *why) when the scan leaves the frame or its reach first.
bool NextRedRun(const ImageView& image, const DetectorOptions& options, cv::Point2f centre,
                cv::Point2f direction, float reference_red, float red_thresh, int reach, int* k,
                float* deepest_a, RejectReason* why) {
  const float clearly_inside =
      reference_red - red_thresh + static_cast<float>(ColorTable::kCoarseErrorBound);
  int consecutive = 0;
  *deepest_a = reference_red;
  for (; *k <= reach; ++*k) {
    // Outside a run, the pixels clearly short of the threshold change
    // nothing below: passed over eight at a time.
    if (consecutive == 0) {
      *k = image.FirstNotClearlyAbove(centre.x, centre.y, direction.x, direction.y, *k, reach,
                                      clearly_inside);
      if (*k > reach) break;
    }
    const cv::Point2f p = centre + static_cast<float>(*k) * direction;
    const int x = RoundToInt(p.x), y = RoundToInt(p.y);
    if (!image.Contains(x, y)) break;
    // Clearly short of the threshold by the coarse a*: the exact one is
    // not needed (as in ScanBorder).
    if (static_cast<float>(image.CoarseA(x, y)) > clearly_inside) {
      consecutive = 0;
      *deepest_a = reference_red;
      continue;
    }
    const float a = image.A(x, y);
    if (reference_red - a > red_thresh) {
      *deepest_a = std::min(*deepest_a, a);
      if (++consecutive == options.border_run) {
        // On a blurred edge the run may end on the slope: look a few pixels on.
        for (int j = *k + 1; j <= *k + kGreenLookAhead; ++j) {
          const cv::Point2f q = centre + static_cast<float>(j) * direction;
          const int qx = RoundToInt(q.x), qy = RoundToInt(q.y);
          if (!image.Contains(qx, qy)) break;
          *deepest_a = std::min(*deepest_a, image.A(qx, qy));
        }
        return true;
      }
    } else {
      consecutive = 0;
      *deepest_a = reference_red;
    }
  }
  *why = RejectReason::kNoRedGreenBorder;
  return false;
}

// One scan of a centring pass: from the pass's centre along `direction`,
// with its ReferenceRed and thresholds (CentringPass), and the borders the
// pass has found so far (`done`: their directions, as bits).
struct PassScan {
  cv::Point2f centre, direction;
  float reference_red, red_thresh, min_drop, max_green_a;
  const std::array<cv::Point2f, 8>* border;
  unsigned done;
};

// The red's peak: its a* and place (*peak_at), sampled half way from the
// centre to each border found so far, the centre's own a* (ReferenceRed)
// to start from.
float PeakRed(const ImageView& image, const PassScan& scan, cv::Point* peak_at) {
  float peak_red = scan.reference_red;
  *peak_at = cv::Point(RoundToInt(scan.centre.x), RoundToInt(scan.centre.y));
  for (int j = 0; j < 8; ++j) {
    if (!(scan.done >> j & 1u)) continue;
    const cv::Point2f q = 0.5f * (scan.centre + (*scan.border)[j]);
    const cv::Point at(RoundToInt(q.x), RoundToInt(q.y));
    const float a = image.A(at.x, at.y);
    if (a > peak_red) {
      peak_red = a;
      *peak_at = at;
    }
  }
  return peak_red;
}

// What a run past the red threshold turned out to be (JudgeRun).
enum class RunVerdict { kGreen, kDip, kRejected };

// Whether the run a scan ended on (its lowest a* `deepest_a`, its last
// pixel at step k) is a tag's green past the red. Past the border lies a
// tag's green: far less red than its red, and green. Most red things that
// are not tags (bricks, skin, wood, a red sign on a wall) meet grey, white
// or black here and are dropped after one scan instead of eight per pass.
// Where only a cast or dim light could make this a tag's green, one ring
// scan finds the candidate's white and the colours are judged in that
// light, once (*in_own_light). A red paler than kMinTagRedA is judged in
// its own light too, as is a drop that is a tag's only from the red's peak
// (kPeakCheckDrop). kDip: neither, the scan may go on past it;
// kRejected (and *why): the colours failed in the candidate's own light.
RunVerdict JudgeRun(const ImageView& image, const DetectorOptions& options, const PassScan& scan,
                    float deepest_a, int k, RingScanBuffers* buffers, bool* in_own_light,
                    RejectReason* why) {
  const float drop = scan.reference_red - deepest_a;
  bool green = GreenPastRed(scan.reference_red, deepest_a, scan.min_drop, scan.max_green_a);
  bool by_peak = false;
  cv::Point peak_at;
  if (!green && scan.done != 0 && drop >= kPeakCheckDrop * scan.min_drop &&
      drop >= kRedDipDepth * scan.red_thresh) {
    const float peak_red = PeakRed(image, scan, &peak_at);
    green = by_peak = GreenPastRed(peak_red, deepest_a, scan.min_drop, scan.max_green_a);
  }
  if (green && !by_peak && scan.reference_red >= static_cast<float>(kMinTagRedA))
    return RunVerdict::kGreen;
  if (!green && !(options.cast_seeds && GreenPastRedInACast(scan.reference_red, deepest_a,
                                                            scan.min_drop, scan.max_green_a)))
    return RunVerdict::kDip;
  if (!*in_own_light) {
    const int skip = std::max(0, k - 2 * options.border_run);
    // A drop judged from the red's peak has its red judged there too.
    const cv::Point red_at =
        by_peak ? peak_at : cv::Point(RoundToInt(scan.centre.x), RoundToInt(scan.centre.y));
    *in_own_light = ColoursInProbeLight(image, options, scan.centre, red_at, scan.direction, skip,
                                        k + kProbeSlack - skip, scan.reference_red, buffers);
  }
  if (*in_own_light) return RunVerdict::kGreen;
  *why = green && !by_peak ? RejectReason::kPaleRed : RejectReason::kNotGreen;
  return RunVerdict::kRejected;
}

// A centring pass's scan along one direction, from step *k on, to the
// red/green border: the end of the first run past the red threshold that
// is a tag's green (JudgeRun), left on *k. A run that stays within
// kRedDipDepth thresholds of the red is a dip inside it, not a border: the
// sensor noise of a dim frame (a* from 15 to 29 across one red cell at
// L* 21) makes runs of M pixels below the threshold. The scan goes on past
// at most kMaxRedDips of them. False (and *why) otherwise.
bool ScanToGreen(const ImageView& image, const DetectorOptions& options, const PassScan& scan,
                 int reach, RingScanBuffers* buffers, bool* in_own_light, int* k,
                 RejectReason* why) {
  for (int dips = 0;; ++dips) {
    float deepest_a = 0;
    if (!NextRedRun(image, options, scan.centre, scan.direction, scan.reference_red,
                    scan.red_thresh, reach, k, &deepest_a, why)) {
      return false;
    }
    switch (JudgeRun(image, options, scan, deepest_a, *k, buffers, in_own_light, why)) {
      case RunVerdict::kGreen:
        return true;
      case RunVerdict::kRejected:
        return false;
      case RunVerdict::kDip:
        break;
    }
    if (dips == kMaxRedDips || scan.reference_red - deepest_a >= kRedDipDepth * scan.red_thresh) {
      *why = RejectReason::kNotGreen;
      return false;
    }
    ++*k;
  }
}

// Step 1: the red/green border in the eight directions from `centre`, into
// `border`. False (and *why) when a scan leaves the frame or reach, or finds
// no tag green past the red.
bool CentringPass(const ImageView& image, const DetectorOptions& options, cv::Point2f centre,
                  float reference_red, int reach, RingScanBuffers* buffers, bool* in_own_light,
                  std::array<cv::Point2f, 8>* border, RejectReason* why) {
  PassScan scan{centre,
                cv::Point2f(),
                reference_red,
                RedGreenThresh(options, reference_red),
                kMinGreenDropFraction * static_cast<float>(options.adiff_thresh),
                static_cast<float>(options.max_green_a),
                border,
                0};
  for (int i : kCentringOrder) {
    // Red -> green only: the a* drop of the full scan, without the rings.
    scan.direction = kScanDirections[i];
    int k = 1;
    if (!ScanToGreen(image, options, scan, reach, buffers, in_own_light, &k, why)) return false;
    (*border)[i] = centre + (static_cast<float>(k - options.border_run) + 0.5f) * scan.direction;
    // Once the opposite scan is in: the red's width across the centre.
    scan.done |= 1u << i;
    const int opposite = (i + 4) % 8;
    if ((scan.done >> opposite & 1u) &&
        cv::norm((*border)[i] - (*border)[opposite]) < kMinRedSpanPx) {
      *why = RejectReason::kRedTooSmall;
      return false;
    }
  }
  return true;
}

// Step 3: whether the candidate's red and green, seen in its own light
// (TagLight: the quiet zone's white from the final scans), are a tag's: the
// red at the centre at least kMinTagRedA, the greens where the scans met
// them (their median) below DetectorOptions::max_green_a. False (and *why)
// otherwise, or when no white can be settled.
bool ColoursInOwnLight(const ImageView& image, const DetectorOptions& options, cv::Point2f centre,
                       const std::array<cv::Point, 4>& greens, TagLight* light, RejectReason* why) {
  if (!light->Settle()) {
    *why = RejectReason::kRingScan;
    return false;
  }
  const int cx = RoundToInt(static_cast<double>(centre.x));
  const int cy = RoundToInt(static_cast<double>(centre.y));
  if (light->BalancedAt(image, cv::Point(cx, cy)).a < static_cast<float>(kMinTagRedA)) {
    *why = RejectReason::kPaleRed;
    return false;
  }
  std::array<float, 4> green_a;
  for (int i = 0; i < 4; ++i) green_a[i] = light->BalancedAt(image, greens[i]).a;
  std::sort(green_a.begin(), green_a.end());
  if (0.5f * (green_a[1] + green_a[2]) >= static_cast<float>(options.max_green_a)) {
    *why = RejectReason::kNotGreen;
    return false;
  }
  return true;
}

// Step 4: whether the ring widths along each of the final scans fit a tag.
bool RingProportionsFit(const Candidate& candidate) {
  for (size_t i = 0; i < candidate.points[kRedGreen].size(); ++i) {
    const float red = cv::norm(candidate.points[kRedGreen][i] - candidate.centre);
    const float green = cv::norm(candidate.points[kGreenBlack][i] - candidate.points[kRedGreen][i]);
    const float black =
        cv::norm(candidate.points[kBlackWhite][i] - candidate.points[kGreenBlack][i]);
    if (green < kMinRingOverRed * red || green > kMaxRingOverRed * red + kRingSlackPx ||
        black < kMinRingOverRed * red || black > kMaxRingOverRed * red + kRingSlackPx ||
        black < kMinBlackOverGreen * green - 1.f || black > kMaxBlackOverGreen * green + 1.f) {
      return false;
    }
  }
  return true;
}

}  // namespace

RejectedRegion RejectedRegion::Around(const std::array<cv::Point2f, 8>& red_border) {
  RejectedRegion region;
  const cv::Point2f middle = PolygonCentroid(red_border);
  for (int i = 0; i < 8; ++i) {
    const cv::Point2f out = red_border[i] - middle;
    const float length = std::sqrt(out.dot(out));
    region.border[i] =
        length > 1e-3f && std::isfinite(length)
            ? red_border[i] +
                  out * ((kRejectedRegionGrowth * length + kRejectedRegionMarginPx) / length)
            : red_border[i];
  }
  region.min_x = region.max_x = region.border[0].x;
  region.min_y = region.max_y = region.border[0].y;
  for (const cv::Point2f& p : region.border) {
    region.min_x = std::min(region.min_x, p.x);
    region.max_x = std::max(region.max_x, p.x);
    region.min_y = std::min(region.min_y, p.y);
    region.max_y = std::max(region.max_y, p.y);
  }
  return region;
}

bool RejectedRegion::BorderContains(cv::Point2f p) const {
  bool inside = false;
  for (size_t i = 0, j = border.size() - 1; i < border.size(); j = i++) {
    const cv::Point2f& a = border[i];
    const cv::Point2f& b = border[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y))
      inside = !inside;
  }
  return inside;
}

SeedAdmission AdmitSeed(std::vector<RejectedRegion>* rejected, cv::Point2f seed, int* region) {
  if (!rejected) return SeedAdmission::kFree;
  int retried = -1;
  for (size_t i = 0; i < rejected->size(); ++i) {
    if (!(*rejected)[i].Contains(seed)) continue;
    if ((*rejected)[i].retries == 0) return SeedAdmission::kDropped;
    retried = static_cast<int>(i);
  }
  if (retried < 0) return SeedAdmission::kFree;
  --(*rejected)[retried].retries;
  if (region) *region = retried;
  return SeedAdmission::kRetry;
}

void ForgetRegionsAbove(float y, std::vector<RejectedRegion>* regions) {
  regions->erase(std::remove_if(regions->begin(), regions->end(),
                                [y](const RejectedRegion& region) { return region.max_y < y; }),
                 regions->end());
}

namespace {

// InitialScan's candidate as it is centred: the centre and ReferenceRed as
// they move, the red/green border last found around it, and the region
// that border would reject (RejectedRegion::Around), once there is one.
struct Centring {
  cv::Point2f centre;
  float reference_red = 0;
  std::array<cv::Point2f, 8> border;
  RejectedRegion region;
  bool have_region = false;
  bool converged = false;  // The centre converged; the final scans follow.
  // Its colours were a tag's only in its own light (ColoursInProbeLight):
  // a cast or dim light explained them.
  bool judged_in_own_light = false;
};

// Rejects the candidate for `reason`: leaves the last centre and red/green
// border in it, for DetectionResult::rejected, and remembers its region.
// Returns false.
bool Reject(const Centring& centring, RejectReason reason, Candidate* candidate,
            std::vector<RejectedRegion>* rejected, RejectReason* why) {
  // A retry that fails adds no region: its region's retries bound the
  // seeds spent on the red. Nor does a red whose colours passed only in
  // its own light: the drops a cast or dim light explains can also be the
  // way out of a large red object that is no tag, into the card of a tag
  // beside it, and its region would then drop that tag's seeds. With
  // cast_seeds, a red-brown background under a warm cast so took a 63 px
  // tag (camera set, frame 3924); on the camera set's 8,000 frames the
  // defaults find the same tags in the same time without these regions,
  // and with cast_seeds that tag is found and none lost.
  if (rejected && centring.have_region && !candidate->retry && !centring.judged_in_own_light) {
    candidate->region = static_cast<int>(rejected->size());
    rejected->push_back(centring.region);
    if (centring.converged && reason >= RejectReason::kRingScan)
      rejected->back().retries = kCentredRedRetries;
  }
  candidate->centre = centring.centre;
  candidate->reference_red = centring.reference_red;
  if (centring.have_region) {
    candidate->points[kRedGreen].assign(centring.border.begin(), centring.border.end());
    candidate->enclosed = true;
    candidate->red_border = centring.border;
  }
  *why = reason;
  return false;
}

// A candidate from a seed at `centre`, nothing found yet.
void StartCandidate(cv::Point2f centre, Candidate* candidate) {
  candidate->centre = centre;
  candidate->enclosed = false;
  candidate->retry = false;
  candidate->region = -1;
  candidate->fits_swapped_print = false;
  candidate->light = TagLight();
  for (auto& ring : candidate->points) ring.clear();
}

// The converged centre, its ReferenceRed and the red/green border around
// it, into the candidate (enclosed by green).
void SettleCentre(const Centring& centring, Candidate* candidate) {
  candidate->centre = centring.centre;
  candidate->reference_red = centring.reference_red;
  candidate->enclosed = true;
  candidate->red_border = centring.border;
}

// Step 1, once: re-centres on the centroid of the polygon of red/green
// border points CentringPass finds in eight directions, the centre's a*
// the next ReferenceRed; *converged when the centre moved less than
// kConvergedPx. After the first pass the centre lies well inside the red
// region, and a tag shows all three rings from there in each axis direction
// (the final scans ask the same of the converged centre, in all four). Red
// things that are not tags (sweets, paint, skin next to something green)
// rarely do, and are dropped there instead of after several more passes of
// eight scans. False (and *why) when the candidate is not a tag's.
bool Recentre(const ImageView& image, const DetectorOptions& options, int reach, bool first_pass,
              RingScanBuffers* buffers, bool* in_own_light, Centring* centring, bool* converged,
              RejectReason* why) {
  const float red_thresh = RedGreenThresh(options, centring->reference_red);
  if (!CentringPass(image, options, centring->centre, centring->reference_red, reach, buffers,
                    in_own_light, &centring->border, why))
    return false;
  centring->region = RejectedRegion::Around(centring->border);
  centring->have_region = true;
  const cv::Point2f next = PolygonCentroid(centring->border);
  if (!(std::isfinite(next.x) && std::isfinite(next.y))) {
    *why = RejectReason::kNoRedGreenBorder;
    return false;
  }
  *converged = std::abs(next.x - centring->centre.x) < kConvergedPx &&
               std::abs(next.y - centring->centre.y) < kConvergedPx;
  centring->centre = next;
  // The clamping overload: the centroid of a nearly flat polygon can be
  // anywhere.
  const int cx = RoundToInt(static_cast<double>(next.x));
  const int cy = RoundToInt(static_cast<double>(next.y));
  if (!image.Contains(cx, cy)) {
    *why = RejectReason::kCentreNotRed;
    return false;
  }
  const float centre_red = image.MeanA3x3(cx, cy);
  // The centre of a tag is red: if re-centring left the red, this is not one.
  if (centre_red < centring->reference_red - red_thresh) {
    *why = RejectReason::kCentreNotRed;
    return false;
  }
  centring->reference_red = centre_red;
  if (first_pass && !*converged) {
    for (int i : kEarlyRingDirections) {
      RingHits hits;
      if (!ScanRings(image, options, next, kScanDirections[i], centring->reference_red, buffers,
                     &hits)) {
        *why = RejectReason::kRingScan;
        return false;
      }
    }
  }
  return true;
}

// Step 2: the three rings in the four axis directions from the converged
// centre seed the candidate's polygons, and its light (the quiet zone's
// whites); greens[] gets where each scan found the green ring.
bool FinalScans(const ImageView& image, const DetectorOptions& options, RingScanBuffers* buffers,
                Candidate* candidate, std::array<cv::Point, 4>* greens) {
  candidate->scan_directions.clear();
  for (int i = 0; i < 8; i += 2) {
    const cv::Point2f direction = kScanDirections[i];
    RingHits hits;
    if (!ScanRings(image, options, candidate->centre, direction, candidate->reference_red, buffers,
                   &hits))
      return false;
    for (int ring = 0; ring < kNumRings; ++ring)
      candidate->points[ring].push_back(hits.border[ring]);
    candidate->scan_directions.push_back(direction);
    candidate->light.AddWhite(image, hits.white_at);
    (*greens)[i / 2] = hits.green_at;
  }
  return true;
}

}  // namespace

bool InitialScan(const ImageView& image, const DetectorOptions& options, cv::Point seed, Seed kind,
                 RingScanBuffers* buffers, Candidate* candidate,
                 std::vector<RejectedRegion>* rejected, RejectReason* why) {
  Centring centring;
  centring.centre = cv::Point2f(static_cast<float>(seed.x), static_cast<float>(seed.y));
  StartCandidate(centring.centre, candidate);
  const SeedAdmission admission = AdmitSeed(rejected, centring.centre, &candidate->region);
  if (admission == SeedAdmission::kDropped) {
    *why = RejectReason::kInRejectedRegion;
    return false;
  }
  candidate->retry = admission == SeedAdmission::kRetry;
  // The seed may sit on the blurred edge of the red; the reddest of it and
  // its neighbourhood is the better ReferenceRed.
  centring.reference_red = std::max(image.A(seed.x, seed.y), image.MeanA3x3(seed.x, seed.y));
  bool in_own_light = false;
  auto reject = [&](RejectReason reason) {
    centring.judged_in_own_light = in_own_light;
    return Reject(centring, reason, candidate, rejected, why);
  };
  // A tag's red half-width is under half the frame unless the tag is larger
  // than the frame.
  const int reach = std::max(image.width(), image.height()) / 2;
  if (centring.reference_red <
      (options.cast_seeds ? kMinSeedRedA : static_cast<float>(kMinTagRedA)))
    return reject(RejectReason::kPaleRed);
  // A seed that only a cast or dim light could make a tag's, or a red paler
  // than kMinTagRedA, must show a tag's colours in its own light first: one
  // ring scan back along the row, where the rise came from (the seed lies
  // at the red's edge, so the rings follow within a few cells).
  if (kind == Seed::kInACast || centring.reference_red < static_cast<float>(kMinTagRedA)) {
    if (!ColoursInProbeLight(image, options, centring.centre, seed, kScanDirections[4], 0,
                             2 * options.step + kProbeSlack, centring.reference_red, buffers)) {
      return reject(RejectReason::kPaleRed);
    }
    in_own_light = true;
  }
  // Step 1, repeated. The paper averages the four axis scans, but on a
  // strongly sheared view (tilt and rotation together) that iteration
  // oscillates instead of converging; the centroid does not.
  bool converged = false;
  for (int iteration = 0; iteration < kMaxCentreIterations && !converged; ++iteration) {
    RejectReason pass_why;
    if (!Recentre(image, options, reach, iteration == 0, buffers, &in_own_light, &centring,
                  &converged, &pass_why))
      return reject(pass_why);
  }
  if (!converged) return reject(RejectReason::kNoConvergence);
  centring.converged = true;
  SettleCentre(centring, candidate);
  std::array<cv::Point, 4> greens;
  if (!FinalScans(image, options, buffers, candidate, &greens))
    return reject(RejectReason::kRingScan);
  if (!RingProportionsFit(*candidate)) return reject(RejectReason::kRingProportions);
  // Step 3: the red and the green in the candidate's own light.
  RejectReason colours_why;
  if (!ColoursInOwnLight(image, options, centring.centre, greens, &candidate->light, &colours_why))
    return reject(colours_why);
  return true;
}

}  // namespace chromatag::internal
