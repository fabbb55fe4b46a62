// Algorithm 1 of the paper, stage by stage (each declared in its own header).
#include "chromatag/detector/detector.h"

#include <chrono>
#include <mutex>
#include <utility>
#include <vector>

#include "build_polygon.h"
#include "candidate.h"
#include "chromatag/detector/pose.h"
#include "decode.h"
#include "find_adiff.h"
#include "geometry.h"
#include "grow_region.h"
#include "initial_scan.h"
#include "poly_to_quad.h"
#include "quad_from_scans.h"
#include "scratch.h"
#include "stage_switches.h"

namespace chromatag {

const char* StageName(Stage stage) {
  switch (stage) {
    case Stage::kFindADiff:
      return "FindADiff";
    case Stage::kInitialScan:
      return "InitialScan";
    case Stage::kBuildPolygon:
      return "BuildPolygon";
    case Stage::kPolyToQuad:
      return "PolyToQuad";
    case Stage::kDecode:
      return "Decode";
    case Stage::kGrowRegion:
      return "GrowRegion";
  }
  return "?";
}

const char* RejectReasonName(RejectReason reason) {
  switch (reason) {
    case RejectReason::kInRejectedRegion:
      return "in rejected region";
    case RejectReason::kPaleRed:
      return "pale red";
    case RejectReason::kNoRedGreenBorder:
      return "no red/green border";
    case RejectReason::kNotGreen:
      return "not green past the red";
    case RejectReason::kCentreNotRed:
      return "centre not red";
    case RejectReason::kRedTooSmall:
      return "red too small";
    case RejectReason::kNoConvergence:
      return "centre did not converge";
    case RejectReason::kRingScan:
      return "ring scan failed";
    case RejectReason::kRingProportions:
      return "ring proportions";
    case RejectReason::kPolygonScan:
      return "polygon scan failed";
    case RejectReason::kNotConvex:
      return "not convex";
    case RejectReason::kPolygonUnfinished:
      return "polygon did not converge";
    case RejectReason::kNoQuad:
      return "no quad";
    case RejectReason::kNotNested:
      return "quads not nested";
    case RejectReason::kRefineFailed:
      return "sub-pixel sides failed";
    case RejectReason::kNoFamilyFits:
      return "no family fits";
    case RejectReason::kWeakChroma:
      return "weak red/green";
    case RejectReason::kLowMargin:
      return "low decision margin";
    case RejectReason::kUnknownCode:
      return "unknown code";
    case RejectReason::kDoubtfulCorrection:
      return "doubtful correction";
    case RejectReason::kSwappedPrint:
      return "fits a swapped print";
    case RejectReason::kNoQuietZone:
      return "no quiet zone";
    case RejectReason::kSquareOpen:
      return "black square open";
    case RejectReason::kSquareNotQuad:
      return "black square not a quad";
    case RejectReason::kNoInnerRings:
      return "no inner rings";
  }
  return "?";
}

Stage StageOf(RejectReason reason) {
  if (reason <= RejectReason::kRingProportions) return Stage::kInitialScan;
  if (reason <= RejectReason::kPolygonUnfinished) return Stage::kBuildPolygon;
  if (reason <= RejectReason::kRefineFailed) return Stage::kPolyToQuad;
  if (reason <= RejectReason::kSwappedPrint) return Stage::kDecode;
  return Stage::kGrowRegion;
}

namespace {

// The Scratch of the Detects in flight: each takes one for its frame and
// gives it back at the end, so that several threads can share a Detector and
// a warm Detect allocates no scratch. One is made when none is free: as many
// are kept as Detects ever ran at once. The lock is held only to take or
// give back, and giving back never allocates (room for every Scratch made is
// reserved when it is made), so that it cannot throw from a destructor.
class ScratchPool {
 public:
  std::unique_ptr<internal::Scratch> Take() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!free_.empty()) {
      std::unique_ptr<internal::Scratch> scratch = std::move(free_.back());
      free_.pop_back();
      return scratch;
    }
    auto scratch = std::make_unique<internal::Scratch>();
    free_.reserve(++made_);
    return scratch;
  }
  void GiveBack(std::unique_ptr<internal::Scratch> scratch) noexcept {
    std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(scratch));
  }

 private:
  std::mutex mutex_;
  std::vector<std::unique_ptr<internal::Scratch>> free_;
  size_t made_ = 0;
};

// A Scratch taken from a pool for the lease's lifetime.
class ScratchLease {
 public:
  explicit ScratchLease(ScratchPool* pool) : pool_(pool), scratch_(pool->Take()) {}
  ~ScratchLease() { pool_->GiveBack(std::move(scratch_)); }
  ScratchLease(const ScratchLease&) = delete;
  ScratchLease& operator=(const ScratchLease&) = delete;

  internal::Scratch& operator*() const { return *scratch_; }

 private:
  ScratchPool* pool_;
  std::unique_ptr<internal::Scratch> scratch_;
};

}  // namespace

struct Detector::Impl {
  DetectorOptions options;
  internal::StageSwitches switches;
  std::vector<internal::FamilyDecoder> families;
  // The colour table: the shared one, or for a white balance this
  // detector's own, with the gains folded in (kernels/color_table.h).
  std::unique_ptr<const internal::ColorTable> own_table;
  const internal::ColorTable* table = nullptr;
  // The vector kernels for this CPU, chosen once here (kernels/kernels.h).
  const internal::Kernels* kernels = nullptr;
  ScratchPool scratch_pool;  // Detect is const; the pool is what it may change.
};

namespace {

using Clock = std::chrono::steady_clock;

double MicrosecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

// What a rejected candidate looked like when `stage` abandoned it (see
// RejectedCandidate::outline).
RejectedCandidate Rejection(const internal::Candidate& candidate, cv::Point seed,
                            RejectReason reason) {
  RejectedCandidate out;
  out.stage = StageOf(reason);
  out.reason = reason;
  out.seed = seed;
  out.centre = candidate.centre;
  switch (out.stage) {
    case Stage::kInitialScan:
      out.outline = candidate.points[internal::kRedGreen];
      break;
    case Stage::kBuildPolygon:
      out.outline = internal::ClockwiseHull(candidate.points[internal::kBlackWhite]);
      break;
    default:
      if (reason == RejectReason::kNoQuad || reason == RejectReason::kNotNested) {
        out.outline = internal::ClockwiseHull(candidate.points[internal::kBlackWhite]);
      } else {
        const internal::Quad& quad = candidate.quads[internal::kBlackWhite];
        out.outline.assign(quad.begin(), quad.end());
      }
  }
  return out;
}

// Whether the centre of `detection` lies inside an area accepted before.
bool InAcceptedArea(const std::vector<internal::DetectedArea>& areas, const Detection& detection) {
  const cv::Vec3d c = detection.image_from_tag * cv::Vec3d(0.5, 0.5, 1.0);
  const cv::Point2d centre(c[0] / c[2], c[1] / c[2]);
  for (const internal::DetectedArea& area : areas) {
    if (area.Contains(centre)) return true;
  }
  return false;
}

// The accepted tag grown by one cell, so that FindADiff skips its quiet zone.
internal::DetectedArea AreaOf(const Detection& detection, int black_square_cells) {
  internal::DetectedArea area;
  const double grow = 1.0 / black_square_cells;
  const double corners[4][2] = {
      {-grow, -grow}, {1 + grow, -grow}, {1 + grow, 1 + grow}, {-grow, 1 + grow}};
  area.min_y = 1e300;
  area.max_y = -1e300;
  for (int i = 0; i < 4; ++i) {
    const cv::Vec3d p = detection.image_from_tag * cv::Vec3d(corners[i][0], corners[i][1], 1.0);
    area.quad[i] = cv::Point2d(p[0] / p[2], p[1] / p[2]);
    area.min_y = std::min(area.min_y, area.quad[i].y);
    area.max_y = std::max(area.max_y, area.quad[i].y);
  }
  return area;
}

}  // namespace

Detector::Detector(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Detector::~Detector() = default;

const DetectorOptions& Detector::options() const { return impl_->options; }

namespace internal {

struct DetectorAccess {
  static std::unique_ptr<Detector> Create(const DetectorOptions& options,
                                          const StageSwitches& switches, std::string* error);
};

std::unique_ptr<Detector> CreateDetector(const DetectorOptions& options,
                                         const StageSwitches& switches, std::string* error) {
  return DetectorAccess::Create(options, switches, error);
}

}  // namespace internal

std::unique_ptr<Detector> Detector::Create(const DetectorOptions& options, std::string* error) {
  return internal::DetectorAccess::Create(options, internal::StageSwitches{}, error);
}

std::unique_ptr<Detector> internal::DetectorAccess::Create(const DetectorOptions& options,
                                                           const StageSwitches& switches,
                                                           std::string* error) {
  if (!options.IsValid(error)) return nullptr;
  auto impl = std::make_unique<Detector::Impl>();
  impl->options = options;
  impl->switches = switches;
  for (const std::string& name : options.families) {
    internal::FamilyDecoder entry;
    entry.family = TagFamily::Load(name, error);
    if (!entry.family) return nullptr;
    bool duplicate = false;
    for (const auto& other : impl->families) duplicate |= other.family == entry.family;
    if (duplicate) continue;
    const int radius =
        options.max_hamming < 0 ? CodeDecoder::DefaultRadius(*entry.family) : options.max_hamming;
    entry.decoder = CodeDecoder::Create(entry.family, radius, error);
    if (!entry.decoder) return nullptr;
    entry.swapped_codes = internal::SwappedCodes(*entry.family);
    entry.oriented_codes = internal::OrientedCodes(*entry.family);
    entry.colour_split_read = switches.colour_split_read;
    entry.misfit_ratio_read = switches.misfit_ratio_read;
    impl->families.push_back(std::move(entry));
  }
  // options() names the families as the library does ("16h5" for "tag16h5"),
  // once each.
  impl->options.families.clear();
  for (const auto& entry : impl->families) impl->options.families.push_back(entry.family->name());
  if (options.white_balance == internal::ColorTable::kNoGains) {
    impl->table = &internal::ColorTable::Get();
  } else {
    impl->own_table = std::make_unique<const internal::ColorTable>(options.white_balance);
    impl->table = impl->own_table.get();
  }
  impl->kernels = &internal::Kernels::ForCpu();
  return std::unique_ptr<Detector>(new Detector(std::move(impl)));
}

DetectionResult Detector::Detect(const cv::Mat& image, PixelOrder order) const {
  DetectionResult result;
  Detect(image, order, &result);
  return result;
}

namespace {

// One frame's way through the stages from each seed (Algorithm 1, steps 2
// to 5): what every stage is handed, and the summary its times and
// rejections go to.
class FrameStages {
 public:
  FrameStages(const internal::ImageView& view, const DetectorOptions& options,
              const internal::StageSwitches& switches,
              const std::vector<internal::FamilyDecoder>& families, internal::Scratch* scratch,
              DetectionResult* result)
      : view_(view),
        options_(options),
        switches_(switches),
        families_(families),
        scratch_(*scratch),
        result_(*result),
        summary_(result->summary) {}

  // InitialScan, then the fast path (QuadsFromScans) or, for a candidate it
  // cannot finish, the paper's way through BuildPolygon, PolyToQuad and
  // Decode; GrowRegion for a candidate they lose. Whether a tag was found,
  // into *detection.
  bool FromSeed(cv::Point seed, internal::Seed kind, Detection* detection) {
    return (Run(Stage::kInitialScan,
                [&] {
                  return internal::InitialScan(view_, options_, seed, kind, &scratch_.ring_scan,
                                               &scratch_.candidate, &scratch_.rejected, &why_);
                }) &&
            (FastPath(detection) || SlowPath(detection))) ||
           GrowLost(seed, detection);
  }

  // Reports `detection`, with its pose, unless it is a tag already accepted
  // in this frame, found again from another seed (one outside its area,
  // whose scans still led to it: under a cast the quiet zone or the card
  // around it can seed).
  void Accept(Detection* detection) {
    if (InAcceptedArea(scratch_.areas, *detection)) return;
    if (options_.camera && options_.tag_size > 0) {
      const Clock::time_point start = Clock::now();
      detection->has_pose =
          EstimateTagPose(*detection, *options_.camera, options_.tag_size, &detection->pose);
      summary_.pose_time_us += MicrosecondsSince(start);
    }
    scratch_.areas.push_back(AreaOf(*detection, detection->family->black_square_cells()));
    result_.detections.push_back(std::move(*detection));
  }

 private:
  // Runs one stage, adding its time; Run also counts a rejection.
  template <typename Body>
  bool Timed(Stage stage, Body&& body) {
    if (!options_.time_stages) return body();
    const Clock::time_point start = Clock::now();
    const bool passed = body();
    summary_.stage_time_us[static_cast<int>(stage)] += MicrosecondsSince(start);
    return passed;
  }
  template <typename Body>
  bool Run(Stage stage, Body&& body) {
    const bool passed = Timed(stage, body);
    if (!passed) ++summary_.rejected[static_cast<int>(stage)];
    return passed;
  }

  bool Decode(Detection* detection, RejectReason* reason) {
    return internal::DecodeCandidate(view_, options_, switches_, families_, &scratch_.side_fit,
                                     &scratch_.candidate, detection, reason);
  }

  // The fast path's time goes to the stages it stands in for; what it
  // abandons is not a rejection, since the slow path takes it up.
  bool FastPath(Detection* detection) {
    if (!switches_.quads_from_scans || !switches_.refine_corners) return false;
    internal::Candidate& candidate = scratch_.candidate;
    RejectReason ignored;
    const bool found =
        Timed(Stage::kBuildPolygon,
              [&] {
                return internal::QuadsFromScans(view_, options_, &scratch_.ring_scan, &candidate);
              }) &&
        Timed(Stage::kPolyToQuad,
              [&] {
                return internal::NestedAndRefined(view_, switches_, &scratch_.side_fit, &candidate,
                                                  &ignored);
              }) &&
        Timed(Stage::kDecode, [&] { return Decode(detection, &ignored); });
    if (found) ++summary_.fast_path_detections;
    return found;
  }

  bool SlowPath(Detection* detection) {
    internal::Candidate& candidate = scratch_.candidate;
    return Run(Stage::kBuildPolygon,
               [&] {
                 return internal::BuildPolygon(view_, options_, &scratch_.ring_scan,
                                               &scratch_.polygon, &candidate, &why_);
               }) &&
           Run(Stage::kPolyToQuad,
               [&] {
                 return internal::PolyToQuad(view_, switches_, &scratch_.quad_fit,
                                             &scratch_.side_fit, &candidate, &why_);
               }) &&
           Run(Stage::kDecode, [&] { return Decode(detection, &why_); });
  }

  // A candidate the stages lost: grown (GrowRegion) where that is worth it,
  // else rejected. Whether growing found a tag.
  bool GrowLost(cv::Point seed, Detection* detection) {
    internal::Candidate& candidate = scratch_.candidate;
    RejectedCandidate rejection;
    if (options_.report_rejected) rejection = Rejection(candidate, seed, why_);
    const bool after_scan = StageOf(why_) != Stage::kInitialScan;
    if (switches_.grow_regions && internal::WorthGrowing(candidate, why_)) {
      const bool grown = Run(Stage::kGrowRegion, [&] {
        return internal::GrowRegion(view_, options_, families_, &scratch_.region,
                                    &scratch_.quad_fit, &scratch_.side_fit, &candidate, detection,
                                    &why_);
      });
      if (grown) return true;
      rejection.grown = true;
      rejection.grow_reason = why_;
    }
    // InitialScan remembers the regions it rejects; so are those the later
    // stages reject, so that the seeds of later rows skip them once they
    // have had their retries. A retry that fails adds no region. A red read
    // as fitting a swapped print, by any read of any family, keeps no
    // retries: each would be another chance for a swapped print's cells to
    // pass as another ID's (DetectorConditionsTest's swapped-print stress
    // frames).
    if (candidate.enclosed && after_scan && !candidate.retry) {
      candidate.region = static_cast<int>(scratch_.rejected.size());
      scratch_.rejected.push_back(internal::RejectedRegion::Around(candidate.red_border));
      scratch_.rejected.back().retries = internal::kLostRedRetries;
    }
    if (candidate.fits_swapped_print && candidate.region >= 0)
      scratch_.rejected[candidate.region].retries = 0;
    if (options_.report_rejected) result_.rejected.push_back(std::move(rejection));
    return false;
  }

  const internal::ImageView& view_;
  const DetectorOptions& options_;
  const internal::StageSwitches& switches_;
  const std::vector<internal::FamilyDecoder>& families_;
  internal::Scratch& scratch_;
  DetectionResult& result_;
  DetectorSummary& summary_;
  RejectReason why_ = RejectReason::kPaleRed;  // Why the last stage to fail failed.
};

// The frame's total time and, when the stages were timed, FindADiff's:
// what the other stages and the poses did not take.
void FinishTimes(Clock::time_point frame_start, bool stages_timed, DetectorSummary* summary) {
  summary->total_time_us = MicrosecondsSince(frame_start);
  if (!stages_timed) return;
  double others = 0;
  for (int s = 1; s < kNumStages; ++s) others += summary->stage_time_us[s];
  summary->stage_time_us[0] =
      std::max(0.0, summary->total_time_us - others - summary->pose_time_us);
}

}  // namespace

void Detector::Detect(const cv::Mat& image, PixelOrder order, DetectionResult* result) const {
  const Clock::time_point frame_start = Clock::now();
  result->detections.clear();
  result->rejected.clear();
  result->summary = DetectorSummary{};
  if (image.empty() || image.type() != CV_8UC3) return;
  const DetectorOptions& options = impl_->options;
  const internal::ImageView view(image, order, *impl_->table, *impl_->kernels);
  impl_->table->Prefetch(/*coarse=*/!internal::RowScanComputesA(view, options));
  const ScratchLease lease(&impl_->scratch_pool);
  internal::Scratch& scratch = *lease;
  scratch.areas.clear();
  scratch.rejected.clear();
  FrameStages stages(view, options, impl_->switches, impl_->families, &scratch, result);
  DetectorSummary& summary = result->summary;

  // Step 1 (FindADiff) along the sampled rows; the other steps from each
  // seed it finds.
  const int num_rows = internal::NumSampledRows(view.height(), options);
  for (int row = 0; row < num_rows; ++row) {
    internal::RowCursor cursor = internal::SampledRow(view.height(), options, row);
    internal::ForgetRegionsAbove(static_cast<float>(cursor.y), &scratch.rejected);
    cv::Point seed;
    internal::Seed kind = internal::Seed::kNone;
    while (internal::FindADiff(view, options, scratch.areas, &scratch.row_scan, &cursor, &seed,
                               &kind, &summary.rejected[static_cast<int>(Stage::kFindADiff)])) {
      ++summary.seeds;
      Detection detection;
      if (stages.FromSeed(seed, kind, &detection)) stages.Accept(&detection);
    }
  }
  FinishTimes(frame_start, options.time_stages, &summary);
}

}  // namespace chromatag
