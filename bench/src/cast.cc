#include "chromatag/bench/cast.h"

#include <algorithm>
#include <cmath>

#include "dataset_impl.h"

namespace chromatag::bench {
namespace {

// Mixed light: where the blend is half-way and how wide it is, as shares of
// the frame's extent along its direction.
constexpr double kMinBlendCentre = 0.3, kMaxBlendCentre = 0.7;
constexpr double kMinBlendWidth = 0.5, kMaxBlendWidth = 1.0;

double ClampGain(double gain) { return std::clamp(gain, kMinCastGain, kMaxCastGain); }

// One source's gains. Every value is drawn whichever kind of source it is,
// so that the frame's other draws do not depend on the kind.
CastGains DrawSource(Rng& rng) {
  const double kind = rng.Uniform();
  const double red_residual = rng.Uniform(-kNeutralResidual, kNeutralResidual);
  const double blue_residual = rng.Uniform(-kNeutralResidual, kNeutralResidual);
  const double strength = rng.Uniform();
  const bool warm = rng.Uniform() < 0.5;
  const double free_red = rng.Uniform(kMinCastGain, kMaxCastGain);
  const double free_blue = rng.Uniform(kMinCastGain, kMaxCastGain);
  if (kind < kNeutralShare) return {1.0 + red_residual, 1.0 + blue_residual};
  if (kind < kNeutralShare + kAxisShare) {
    // From neutral to (1.5, 0.6) or (0.6, 1.5): the range's ends at full strength.
    const double up = 1.0 + (kMaxCastGain - 1.0) * strength;
    const double down = 1.0 - (1.0 - kMinCastGain) * strength;
    return {ClampGain((warm ? up : down) * (1.0 + red_residual)),
            ClampGain((warm ? down : up) * (1.0 + blue_residual))};
  }
  return {free_red, free_blue};
}

double Smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

}  // namespace

const char* CastKindName(CastKind kind) {
  switch (kind) {
    case CastKind::kNeutral:
      return "neutral";
    case CastKind::kWarm:
      return "warm";
    case CastKind::kCool:
      return "cool";
    case CastKind::kGreen:
      return "green";
    case CastKind::kMagenta:
      return "magenta";
  }
  return "?";
}

CastKind CastKindOf(const CastGains& gains) {
  const double red = std::log(gains.red), blue = std::log(gains.blue);
  const double neutral = std::log(kNeutralFactor);
  if (std::abs(red) <= neutral && std::abs(blue) <= neutral) return CastKind::kNeutral;
  const double warmth = (red - blue) / 2, tint = (red + blue) / 2;
  if (std::abs(warmth) >= std::abs(tint)) return warmth > 0 ? CastKind::kWarm : CastKind::kCool;
  return tint > 0 ? CastKind::kMagenta : CastKind::kGreen;
}

bool IsStrongCast(const CastGains& gains) {
  return std::min(gains.red, gains.blue) <= kStrongLow ||
         std::max(gains.red, gains.blue) >= kStrongHigh;
}

CastGains FrameCast::At(const cv::Point2d& pixel, const cv::Size& size) const {
  if (!mixed) return first;
  const double dx = std::cos(angle), dy = std::sin(angle);
  const double half_w = (size.width - 1) / 2.0, half_h = (size.height - 1) / 2.0;
  const double reach = half_w * std::abs(dx) + half_h * std::abs(dy);
  const double along = 0.5 + ((pixel.x - half_w) * dx + (pixel.y - half_h) * dy) / (2 * reach);
  const double t = Smoothstep((along - centre) / width + 0.5);
  return {(1 - t) * first.red + t * second.red, (1 - t) * first.blue + t * second.blue};
}

cv::Mat FrameCast::GainMap(const cv::Size& size) const {
  cv::Mat map(size, CV_32FC3);
  for (int y = 0; y < size.height; ++y) {
    cv::Vec3f* row = map.ptr<cv::Vec3f>(y);
    for (int x = 0; x < size.width; ++x) {
      const CastGains g = At(cv::Point2d(x, y), size);
      row[x] = {static_cast<float>(g.blue), 1.0f, static_cast<float>(g.red)};
    }
  }
  return map;
}

FrameCast DrawFrameCast(uint64_t seed) {
  Rng rng(seed);
  FrameCast cast;
  cast.first = DrawSource(rng);
  cast.mixed = rng.Uniform() < kMixedShare;
  // The second source leans the other way from the first: cooler when the
  // first is warm or neutral, warmer when it is cool.
  const double shift = rng.Uniform(kMinMixShift, kMaxMixShift);
  const double k = cast.first.red >= cast.first.blue ? 1.0 / shift : shift;
  cast.second = {ClampGain(cast.first.red * k), ClampGain(cast.first.blue / k)};
  cast.angle = rng.Uniform(0.0, 2 * kPi);
  cast.centre = rng.Uniform(kMinBlendCentre, kMaxBlendCentre);
  cast.width = rng.Uniform(kMinBlendWidth, kMaxBlendWidth);
  if (!cast.mixed) cast.second = cast.first;
  return cast;
}

}  // namespace chromatag::bench
