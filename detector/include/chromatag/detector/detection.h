// What the detector returns: detections (spec section 7) and a per-frame
// summary with the time and the rejections of every stage (the paper's
// Tables 2 and 4).
#ifndef CHROMATAG_DETECTOR_DETECTION_H_
#define CHROMATAG_DETECTOR_DETECTION_H_

#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "chromatag/families/family.h"

namespace chromatag {

// The tag's pose: camera_from_tag maps tag coordinates (origin at the tag
// centre, x right, y up, z out of the tag towards the viewer, metres; as
// OpenCV's SOLVEPNP_IPPE_SQUARE) to camera coordinates.
struct TagPose {
  cv::Vec3d rvec;  // Rodrigues rotation of camera_from_tag.
  cv::Vec3d tvec;  // Tag centre in the camera frame, metres.
  // Root mean square reprojection error over the twelve ring corners, pixels.
  double rms_error_px = 0.0;
  // The planar ambiguity: the kept solution's rms error over the other
  // planar solution's (both refined on the twelve corners; as AprilTag 3's
  // err1 / err2). Near 0 the view settles the pose; near 1 the two fit about
  // equally (a small or nearly frontal tag), and the tilt may be mirrored.
  // 0 when there was one solution, or both refined into one (frontal views).
  double ambiguity = 0.0;
  // How far the pose can be trusted: its 6 x 6 covariance in ROS's
  // PoseWithCovariance order and units, row-major: the translation's x, y, z
  // (metres; tvec's units when the tag size is given in another), then a
  // small rotation about the camera's x, y, z axes composed onto the pose
  // (R' = exp([w]x) R: the tag turning about its own centre; radians). The
  // detection's corner covariance carried through the fit, scaled up when
  // the corners fit each other worse than their noise explains; when the
  // other planar solution fits nearly as well, its difference is added in
  // the share the corners give it, so a tilt that may be mirrored shows as
  // a large rotation variance. Over the benchmark's rendered views, errors
  // against the truth fall within it as a Gaussian's would (docs/pose.md,
  // "Uncertainty").
  cv::Matx66d covariance = cv::Matx66d::zeros();
};

struct Detection {
  // The decoded tag's family (16h5 or 36h11): its name, cell layout and
  // codes. Families are loaded once per process and never freed
  // (TagFamily::Load), so the pointer stays valid.
  const TagFamily* family = nullptr;
  int id = -1;
  int hamming = 0;  // Bits corrected.
  // How clearly the shades split: over both colours, the smaller gap between
  // the two b* clusters divided by their pooled spread (at least 1 b* unit).
  // Dimensionless; weak decodes below DetectorOptions::min_decision_margin
  // are rejected unless their code fits the cells closely (the rescue and
  // the soft-decision read, DetectorOptions::max_hamming).
  double decision_margin = 0.0;
  // The black/white border, in the decoded tag's orientation: corner 0 is the
  // top-left of the upright tag, then clockwise. Pixel centres are at integer
  // coordinates (OpenCV's convention). The edges are placed between halfway
  // in linear light (a lens's blur) and halfway in the encoded values
  // (software's), in the share that makes the black ring one cell wide
  // (docs/pose.md, "How it is computed").
  std::array<cv::Point2d, 4> corners;
  // The green/black and red/green borders, in the same order: where the
  // tag's proportions put them, one and two cells inside `corners`
  // (image_from_tag). The black/white border is the tag's strongest edge and
  // a luminance one; the inner ones are weaker, and cameras blur their
  // chroma (JPEG 4:2:0, demosaicing), so located on their own edges they
  // came out worse (commit 16bcecd). Lens distortion
  // across one tag is not modelled here.
  std::array<cv::Point2d, 4> green_corners;
  std::array<cv::Point2d, 4> red_corners;
  // Maps the upright black square, the unit square (0,0)-(1,1) with x right
  // and y down, to image pixels: (0,0) -> corners[0], (1,0) -> corners[1].
  cv::Matx33d image_from_tag;
  // How far `corners` can be trusted: their covariance as x0, y0, x1, y1,
  // ... (the order of `corners`), px^2. The detector estimates it from the
  // scatter of the edge points about each fitted side, how far apart the
  // two edge conventions put the corners, and a floor for what a camera and
  // a print do to an edge that the scatter does not show (docs/pose.md,
  // "Uncertainty"). The inner corners are functions of these four. Zero in
  // a detection made by hand: EstimateTagPose then takes the corners as
  // independent, with the fit's residuals as their spread.
  cv::Matx<double, 8, 8> corner_covariance = cv::Matx<double, 8, 8>::zeros();
  bool has_pose = false;
  TagPose pose;
};

// Algorithm 1's stages, in order, then the second path: a candidate whose red
// is enclosed by green but which the ring scans or later stages lost has its
// black square grown on a grid of pixels, its inner rings placed from it and
// fitted on their edges, and is decoded again.
enum class Stage { kFindADiff = 0, kInitialScan, kBuildPolygon, kPolyToQuad, kDecode, kGrowRegion };
inline constexpr int kNumStages = 6;
const char* StageName(Stage stage);  // "FindADiff", ..., "GrowRegion"

struct DetectorSummary {
  // Wall time spent in each stage, microseconds, with
  // DetectorOptions::time_stages (else zero). FindADiff is the frame's
  // time minus the other stages (its loop encloses them). The fast path's
  // quads count as BuildPolygon, its sub-pixel sides as PolyToQuad and its
  // reads as Decode.
  std::array<double, kNumStages> stage_time_us{};
  // Candidates abandoned by each stage. FindADiff counts rises its fast row
  // scan (an a* good to a few units) suggested but the exact a* did not
  // confirm.
  // What the fast path abandons is not counted: the stages take it up.
  std::array<int, kNumStages> rejected{};
  int seeds = 0;  // Candidates handed to InitialScan.
  // Candidates the fast path (eight ring scans to a quad) took from
  // InitialScan to a detection, without BuildPolygon.
  int fast_path_detections = 0;
  double total_time_us = 0.0;
  double pose_time_us = 0.0;  // Timed apart: in total_time_us, in no stage's time.
};

// Why a stage abandoned a candidate.
enum class RejectReason {
  // InitialScan.
  kInRejectedRegion = 0,  // The seed lies in a red region already rejected in this frame.
  kPaleRed,               // The seed's a* is below kMinTagRedA.
  kNoRedGreenBorder,      // A centring scan met no red/green border (or left the frame).
  kNotGreen,              // Past the red/green border a* does not fall into a green.
  kCentreNotRed,          // Re-centring left the red.
  kRedTooSmall,           // The red is narrower than a tag's the detector could read.
  kNoConvergence,         // The centre did not settle.
  kRingScan,              // A scan from the centre did not cross the three rings.
  kRingProportions,       // The rings' widths are not a tag's.
  // BuildPolygon.
  kPolygonScan,        // A scan towards the largest potential area failed.
  kNotConvex,          // A new border point lies well inside the polygon.
  kPolygonUnfinished,  // Too many scans without converging.
  // PolyToQuad.
  kNoQuad,        // The polygons do not cluster into four sides.
  kNotNested,     // The three quads are not nested, or the outer one is tiny.
  kRefineFailed,  // A side found too few sub-pixel edge points, or a corner jumped.
  // Decode.
  kNoFamilyFits,        // The ring proportions fit no family looked for.
  kWeakChroma,          // Some red cell is not clearly redder than every green one.
  kLowMargin,           // The shades do not split clearly (decision margin).
  kUnknownCode,         // The bits are no code of the family within the radius.
  kDoubtfulCorrection,  // A corrected bit's cell was clearly the other shade.
  kSwappedPrint,        // A 16h5 read fits a tag printed with its shades swapped about as well.
  // GrowRegion (then Decode's reasons).
  kNoQuietZone,    // Profiles out of the red find no dark ring, then no lighter quiet zone.
  kSquareOpen,     // The dark region around the red leaked: larger than any tag's black square.
  kSquareNotQuad,  // The dark region's outline is not a quadrilateral of a tag's size.
  kNoInnerRings,   // No family's green/black and red/green sides were found inside it.
};
inline constexpr int kNumRejectReasons = 25;
const char* RejectReasonName(RejectReason reason);  // "in rejected region", ...
// The stage of Algorithm 1 a reason belongs to (GrowRegion's own four map to
// kGrowRegion; it also fails with Decode's).
Stage StageOf(RejectReason reason);

// A candidate some stage abandoned, for failure analysis and overlays (as
// OpenCV's ArUco returns its rejected candidates). Reported only when
// DetectorOptions::report_rejected is set.
struct RejectedCandidate {
  // Where Algorithm 1's stages abandoned it.
  Stage stage = Stage::kInitialScan;
  RejectReason reason = RejectReason::kPaleRed;
  // Whether GrowRegion tried it too, and why that failed.
  bool grown = false;
  RejectReason grow_reason = RejectReason::kNoQuietZone;
  cv::Point seed;      // FindADiff's sample that started it.
  cv::Point2f centre;  // InitialScan's last centre (the seed if it never moved).
  // The outline known when it was abandoned, clockwise on screen: the outer
  // quad from PolyToQuad on (Decode's rejections included), the hull of the
  // outer border points in BuildPolygon, the red/green border points in
  // InitialScan once a centring pass completed; empty before.
  std::vector<cv::Point2f> outline;
};

struct DetectionResult {
  std::vector<Detection> detections;
  DetectorSummary summary;
  std::vector<RejectedCandidate> rejected;  // Empty unless report_rejected.
};

}  // namespace chromatag

#endif  // CHROMATAG_DETECTOR_DETECTION_H_
