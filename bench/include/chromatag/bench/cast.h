// The camera set's colour casts: white balance left wrong, and mixed light.
//
// A camera multiplies its linear sensor values by white-balance gains before
// it clips them; when the gains do not match the light, every colour shifts.
// The model keeps green at 1 and gives red and blue a gain each in
// [kMinCastGain, kMaxCastGain] (a gain above 1 can clip white, as in a real
// camera). A frame's source is drawn as:
// - kNeutralShare: white-balanced, a residual of up to kNeutralResidual per gain;
// - kAxisShare: a light of another colour temperature than the balance was set
//   for, strength uniform up to the range's ends: warm (tungsten on a daylight
//   balance: red up to 1.5, blue down to 0.6) or cool (daylight on a tungsten
//   balance: red down to 0.6, blue up to 1.5), half each, with the residual;
// - the rest: red and blue gains uniform and independent over the whole range
//   (green and magenta tints, as fluorescent and LED light give, included).
// kMixedShare of the frames are lit by two sources of different colour: the
// second is the first made cooler (red / k, blue * k) when the first is
// warm or neutral, warmer otherwise, k in [kMinMixShift, kMaxMixShift]
// (clipped to the range), and the gains blend smoothly from one to the other across the frame, in a
// random direction, so that the card and the background see different casts.
#ifndef CHROMATAG_BENCH_CAST_H_
#define CHROMATAG_BENCH_CAST_H_

#include <cstdint>

#include <opencv2/core.hpp>

namespace chromatag::bench {

inline constexpr double kMinCastGain = 0.6, kMaxCastGain = 1.5;
inline constexpr double kNeutralShare = 0.3;
inline constexpr double kAxisShare = 0.45;
inline constexpr double kNeutralResidual = 0.04;  // Share of the gain, either way.
inline constexpr double kMixedShare = 0.25;
inline constexpr double kMinMixShift = 1.25, kMaxMixShift = 1.5;

// White-balance gains on linear red and blue; green's is 1.
struct CastGains {
  double red = 1.0;
  double blue = 1.0;
};

// What a reader calls a cast, from the gains (CastKindOf).
enum class CastKind { kNeutral = 0, kWarm = 1, kCool = 2, kGreen = 3, kMagenta = 4 };
inline constexpr int kNumCastKinds = 5;
const char* CastKindName(CastKind kind);  // "neutral", "warm", "cool", "green", "magenta".

// Neutral when both gains lie within kNeutralFactor of 1 either way;
// otherwise the larger of the warm-cool component (log red over blue) and
// the green-magenta one (log red times blue) names it: warm when red
// outweighs blue, magenta when both exceed green.
inline constexpr double kNeutralFactor = 1.1;
CastKind CastKindOf(const CastGains& gains);
// A gain of kStrongLow or less, or of kStrongHigh or more: the ends of the range.
inline constexpr double kStrongLow = 0.7, kStrongHigh = 1.4;
bool IsStrongCast(const CastGains& gains);

// How one frame is lit: one source, or two blending across the frame.
struct FrameCast {
  CastGains first;   // The only source, or the one at the blend's start.
  CastGains second;  // The other source of mixed light.
  bool mixed = false;
  // Mixed light: the blend runs along this direction (radians, image x right
  // and y down); positions along it are shares of the frame's extent, 0 at
  // its first pixel and 1 at its last. Half-way between the sources at
  // `centre`, the blend (smoothstep) spans `width`.
  double angle = 0.0;
  double centre = 0.5;
  double width = 1.0;

  // The gains at a pixel of a frame of `size`.
  CastGains At(const cv::Point2d& pixel, const cv::Size& size) const;
  // Per-pixel gains of a frame of `size` as CV_32FC3 (B, G, R), G = 1.
  cv::Mat GainMap(const cv::Size& size) const;
};

// The cast of one frame, a pure function of `seed`.
FrameCast DrawFrameCast(uint64_t seed);

}  // namespace chromatag::bench

#endif  // CHROMATAG_BENCH_CAST_H_
