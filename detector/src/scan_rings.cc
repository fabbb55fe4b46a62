// The scan primitive shared by InitialScan and BuildPolygon (paper section 4):
// walk outwards pixel by pixel until M successive pixels lie beyond a
// threshold from the reference colour.
#include "scan_rings.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "candidate.h"

namespace chromatag::internal {
namespace {

// What changes at each border. Red -> green is the paper's a* test. Past the
// green ring the strong signal is lightness: the two greens differ by up to
// 9 L* (iccv17 palette) but black is 35 or more below them, and white far
// above black; a* barely changes from black to white.
enum class Border { kRedToGreen, kGreenToBlack, kBlackToWhite };

// How far past a run to follow a blurred edge down to its plateau, pixels
// (Gaussian blur of sigma 2 px spreads an edge over about 4 sigma), and the
// smallest change that counts as still descending (CIELAB units; above the
// 8-bit quantisation of L* and a*).
constexpr int kMaxPlateauSteps = 8;
constexpr float kPlateauTolerance = 0.5f;

// Red half-widths (pixels from the scan's start to the green) up to which the
// green and black rings count as thin (see ScanRings).
constexpr int kThinRingSteps = 12;

// A step whose exact value was not read (ScanBorder).
constexpr float kNotRead = std::numeric_limits<float>::quiet_NaN();

// The border is a template argument throughout: the scans visit every pixel
// on their way, and a branch (and call) per pixel on which channel to read
// cost a fifth of their time.
template <Border border>
float ValueAt(const ImageView& image, int x, int y) {
  if constexpr (border == Border::kRedToGreen) {
    return image.A(x, y);
  } else {
    return image.L(x, y);
  }
}

// How far `value` lies past `reference` towards the next ring's colour (a*
// falls into green, L* falls into black and rises into white).
template <Border border>
float Depth(float reference, float value) {
  return border == Border::kBlackToWhite ? value - reference : reference - value;
}

// Whether a pixel counts towards the M successive ones that make a border.
// Leaving green, a pixel lighter than the green (the white beyond a ring
// thinner than M pixels) counts as well as a darker one.
template <Border border>
bool Beyond(float reference, float value, float thresh) {
  if constexpr (border == Border::kGreenToBlack) return std::abs(reference - value) > thresh;
  return Depth<border>(reference, value) > thresh;
}

struct Crossing {
  cv::Point2f at;      // Sub-pixel border: where the value passes halfway.
  cv::Point2f resume;  // The next ring's reference pixel, where the next scan starts.
  float value_after = 0;
  int steps = 0;  // Steps from the start to `resume`.
};

// The pixel `k` steps from `start` along `direction`.
inline cv::Point StepPixel(cv::Point2f start, cv::Point2f direction, int k) {
  return cv::Point(RoundToInt(start.x + k * direction.x), RoundToInt(start.y + k * direction.y));
}

// ScanBorder's walk: from step 1 on, to the last pixel (*end) of the first
// `run` successive ones beyond `thresh` from `reference`. Each pixel's
// value is read once, into values[k] for step k (the run's pixels are
// looked at again, for the deepest one and the halfway level). False when
// the walk leaves the frame or passes max_steps first.
template <Border border>
bool FindRun(const ImageView& image, cv::Point2f start, cv::Point2f direction, float reference,
             float thresh, int run, int max_steps, float* values, int* end) {
  int consecutive = 0;
  int k = 1;
  // Red -> green: a pixel whose coarse a* is clearly above the threshold is
  // not past it, and its exact a* is not needed below (only the run's pixels
  // and the one before it are read again); most of a red region is passed
  // over with one table read a pixel instead of the exact conversion.
  const float clearly_inside = reference - thresh + ColorTable::kCoarseErrorBound;
  for (; k <= max_steps; ++k) {
    if constexpr (border == Border::kRedToGreen) {
      // Outside a run, eight at a time (the same pixels and tests).
      if (consecutive == 0) {
        const int next = image.FirstNotClearlyAbove(start.x, start.y, direction.x, direction.y, k,
                                                    max_steps, clearly_inside);
        for (; k < next; ++k) values[k] = kNotRead;
        if (k > max_steps) break;
      }
    }
    const cv::Point p = StepPixel(start, direction, k);
    if (!image.Contains(p.x, p.y)) return false;
    if constexpr (border == Border::kRedToGreen) {
      if (static_cast<float>(image.CoarseA(p.x, p.y)) > clearly_inside) {
        values[k] = kNotRead;
        consecutive = 0;
        continue;
      }
    }
    const float value = ValueAt<border>(image, p.x, p.y);
    values[k] = value;
    if (Beyond<border>(reference, value, thresh)) {
      if (++consecutive == run) break;
    } else {
      consecutive = 0;
    }
  }
  *end = k;
  return k <= max_steps;
}

// The next ring's reference: the step of the run's pixel (the run ends at
// step k) deepest into it (the greenest, darkest or lightest), its depth
// into *deepest_depth. On rings thinner than M pixels the run reaches into
// the ring after, and its last pixel would be the wrong colour. On a
// blurred edge the run ends part way down the slope; it is followed on to
// the plateau (values[] read on), so that the next ring's reference (and
// the halfway level) is the ring's colour and not a blend. Stops where the
// value turns back (the ring after, on thin rings) or stays level.
template <Border border>
int DeepestStep(const ImageView& image, cv::Point2f start, cv::Point2f direction, float reference,
                int run, int k, float* values, float* deepest_depth) {
  int deepest = k - run + 1;
  *deepest_depth = -1e30f;
  for (int j = k - run + 1; j <= k; ++j) {
    const float depth = Depth<border>(reference, values[j]);
    if (depth > *deepest_depth) {
      *deepest_depth = depth;
      deepest = j;
    }
  }
  for (int j = k + 1, level = 0; j <= k + kMaxPlateauSteps && level < 2; ++j) {
    const cv::Point p = StepPixel(start, direction, j);
    if (!image.Contains(p.x, p.y)) break;
    values[j] = ValueAt<border>(image, p.x, p.y);
    const float depth = Depth<border>(reference, values[j]);
    if (depth > *deepest_depth + kPlateauTolerance) {
      *deepest_depth = depth;
      deepest = j;
      level = 0;
    } else {
      ++level;
    }
  }
  return deepest;
}

// The border: where the depth passes half the deepest pixel's
// (`deepest_depth`, at step `deepest`), interpolated between the two pixels
// around it; from the step before the run (ending at step k), the
// reference itself if it was not read. The deepest pixel where none passes.
template <Border border>
cv::Point2f HalfwayCrossing(const ImageView& image, cv::Point2f start, cv::Point2f direction,
                            float reference, int run, int k, int deepest, float deepest_depth,
                            const float* values) {
  const float half = 0.5f * deepest_depth;
  float previous_depth = 0.f;  // The reference itself, at the step before the run.
  cv::Point previous = StepPixel(start, direction, k - run);
  if (k - run >= 1 && !std::isnan(values[k - run])) {
    previous_depth = Depth<border>(reference, values[k - run]);
  } else if (image.Contains(previous.x, previous.y)) {
    previous_depth = Depth<border>(reference, ValueAt<border>(image, previous.x, previous.y));
  }
  for (int j = k - run + 1; j <= deepest; ++j) {
    const cv::Point p = StepPixel(start, direction, j);
    const float depth = Depth<border>(reference, values[j]);
    if (depth >= half) {
      const float span = depth - previous_depth;
      const float t = span > 1e-6f ? std::clamp((half - previous_depth) / span, 0.f, 1.f) : 0.5f;
      return cv::Point2f(previous.x + t * (p.x - previous.x), previous.y + t * (p.y - previous.y));
    }
    previous = p;
    previous_depth = depth;
  }
  const cv::Point end = StepPixel(start, direction, deepest);
  return cv::Point2f(static_cast<float>(end.x), static_cast<float>(end.y));
}

// One border along a scan (the paper's scan primitive): the run of `run`
// pixels past `thresh`, the next ring's reference pixel and the sub-pixel
// border before it. False when the scan leaves the frame or max_steps.
template <Border border>
bool ScanBorder(const ImageView& image, cv::Point2f start, cv::Point2f direction, float reference,
                float thresh, int run, int max_steps, RingScanBuffers* buffers,
                Crossing* crossing) {
  std::vector<float>& values = buffers->values;
  const size_t needed = static_cast<size_t>(max_steps) + kMaxPlateauSteps + 2;
  if (values.size() < needed) values.resize(needed);
  int k = 0;
  if (!FindRun<border>(image, start, direction, reference, thresh, run, max_steps, values.data(),
                       &k))
    return false;
  float deepest_depth = 0;
  const int deepest = DeepestStep<border>(image, start, direction, reference, run, k, values.data(),
                                          &deepest_depth);
  const cv::Point end = StepPixel(start, direction, deepest);
  crossing->value_after = values[deepest];
  crossing->resume = cv::Point2f(static_cast<float>(end.x), static_cast<float>(end.y));
  crossing->steps = deepest;
  crossing->at = HalfwayCrossing<border>(image, start, direction, reference, run, k, deepest,
                                         deepest_depth, values.data());
  return true;
}

// The three borders of a scan, and the colours of the green ring and the
// quiet zone where they are their own: the middle of the green ring, and
// half the black ring's width into the quiet zone (at least one cell
// wide), clear of blurred edges.
void SetHits(const Crossing& red_green, const Crossing& green_black, const Crossing& black_white,
             RingHits* hits) {
  hits->border = {red_green.at, green_black.at, black_white.at};
  const cv::Point2f green_middle = 0.5f * (red_green.at + green_black.at);
  const cv::Point2f into_white = black_white.at + 0.5f * (black_white.at - green_black.at);
  hits->green_at = cv::Point(RoundToInt(green_middle.x), RoundToInt(green_middle.y));
  hits->white_at = cv::Point(RoundToInt(into_white.x), RoundToInt(into_white.y));
}

}  // namespace

bool ScanRings(const ImageView& image, const DetectorOptions& options, cv::Point2f start,
               cv::Point2f direction, float reference_red, RingScanBuffers* buffers, RingHits* hits,
               int red_reach) {
  const float thresh = static_cast<float>(options.border_thresh);
  const int run = options.border_run;
  const int reach = red_reach >= 0 ? red_reach : std::max(image.width(), image.height());

  Crossing red_green;
  if (!ScanBorder<Border::kRedToGreen>(image, start, direction, reference_red,
                                       RedGreenThresh(options, reference_red), run, reach, buffers,
                                       &red_green)) {
    return false;
  }
  // ReferenceGreen: a tag's green is far less red than its red (the seed saw
  // a rise above ADiffThresh); half of that allows for blur on small tags.
  if (reference_red - red_green.value_after < 0.5f * static_cast<float>(options.adiff_thresh)) {
    return false;
  }
  const int p = red_green.resume.x, q = red_green.resume.y;
  const float green_l = image.L(p, q);
  // The green ring and the black ring are one cell each, as wide as the red
  // half-width (16h5) or half of it (36h11); allow for perspective.
  const int ring_reach = 3 * red_green.steps + 6;
  // The green and black rings are one cell wide, under 5 px on tags below
  // 30 px; blur and JPEG eat into them from both sides, and M = 3 pixels past
  // the border missed most such tags. On small tags (a narrow red region)
  // their borders need one pixel fewer (at least 2); larger tags keep M, which
  // keeps their border points as steady. Red -> green always keeps M: its
  // border is where candidates that are not tags are sorted out.
  const int ring_run = run > 2 && red_green.steps <= kThinRingSteps ? run - 1 : run;

  Crossing green_black;
  if (!ScanBorder<Border::kGreenToBlack>(image, red_green.resume, direction, green_l,
                                         std::max(thresh, 0.3f * green_l), ring_run, ring_reach,
                                         buffers, &green_black)) {
    return false;
  }
  const float black_l = green_black.value_after;
  // Into white: half way from the black up to the green. ReferenceBlack is
  // the darkest pixel of the run, and on a dim card the sensor's noise
  // spreads the black ring over L* 4-21 (a 164 px tag at L* 18 lost all its
  // scans to bumps inside its black ring at 0.3 of the way); the quiet zone
  // lies above the green.
  Crossing black_white;
  if (!ScanBorder<Border::kBlackToWhite>(image, green_black.resume, direction, black_l,
                                         std::max(thresh, 0.5f * (green_l - black_l)), ring_run,
                                         ring_reach, buffers, &black_white)) {
    return false;
  }
  // The quiet zone is the lightest part of a tag.
  if (black_white.value_after < green_l + thresh) return false;
  SetHits(red_green, green_black, black_white, hits);
  return true;
}

}  // namespace chromatag::internal
