// A candidate's own light (tag_light.h).
#include "tag_light.h"

#include <algorithm>

#include "chromatag/families/color.h"

namespace chromatag::internal {
namespace {

// Linear light of each 8-bit sRGB value.
const std::array<float, 256>& LinearOf() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int v = 0; v < 256; ++v) t[v] = static_cast<float>(Srgb8ToLinear(static_cast<uint8_t>(v)));
    return t;
  }();
  return table;
}

// A white darker than this (linear, per channel) is not divided by: it is
// black or noise, not a quiet zone.
constexpr float kMinWhite = 0.004f;

// The mean 8-bit colour of the 3 x 3 pixels around `at` inside the frame,
// in R, G, B order.
std::array<uint8_t, 3> Mean3x3(const ImageView& image, cv::Point at) {
  int sum[3] = {0, 0, 0}, n = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      if (!image.Contains(at.x + dx, at.y + dy)) continue;
      const uint8_t* p = image.Pixel(at.x + dx, at.y + dy);
      sum[0] += image.R(p);
      sum[1] += image.G(p);
      sum[2] += image.B(p);
      ++n;
    }
  }
  if (n == 0) return {0, 0, 0};
  return {static_cast<uint8_t>((sum[0] + n / 2) / n), static_cast<uint8_t>((sum[1] + n / 2) / n),
          static_cast<uint8_t>((sum[2] + n / 2) / n)};
}

}  // namespace

void TagLight::AddWhite(const ImageView& image, cv::Point at) {
  if (num_whites_ == kMaxWhites) return;
  const std::array<uint8_t, 3> rgb = Mean3x3(image, at);
  for (int c = 0; c < 3; ++c) whites_[c][num_whites_] = LinearOf()[rgb[c]];
  ++num_whites_;
}

bool TagLight::Settle() {
  settled_ = false;
  if (num_whites_ == 0) return false;
  for (int c = 0; c < 3; ++c) {
    float* begin = whites_[c].data();
    float* middle = begin + num_whites_ / 2;
    std::nth_element(begin, middle, begin + num_whites_);
    if (!(*middle >= kMinWhite)) return false;
    gain_[c] = static_cast<float>(kPaperWhiteY / *middle);
  }
  settled_ = true;
  return true;
}

LabF TagLight::BalancedAt(const ImageView& image, cv::Point at) const {
  const std::array<uint8_t, 3> rgb = Mean3x3(image, at);
  return Balanced(image.table(), rgb[0], rgb[1], rgb[2]);
}

}  // namespace chromatag::internal
