#include "chromatag/families/margins.h"

#include <algorithm>
#include <cmath>

namespace chromatag {
namespace {

double CellSpread(const ShadeReading& one, const ShadeReading& zero) {
  // The detector averages 3 x 3 pixels per cell: pixel noise shrinks by 3;
  // the print's own unevenness (spread between repeats) does not.
  const double repeat =
      (one.repeat_spread_b * one.repeat_spread_b + zero.repeat_spread_b * zero.repeat_spread_b) /
      2.0;
  const double pixel = std::max(one.pixel_noise_b, zero.pixel_noise_b) / 3.0;
  return std::sqrt(repeat + pixel * pixel);
}

}  // namespace

Margins MarginsOf(const std::array<ShadeReading, 4>& shades, double white_l, bool seen) {
  auto lab = [&](int i) { return seen ? shades[i].seen : shades[i].lab; };
  const Lab r1 = lab(0), r0 = lab(1), g1 = lab(2), g0 = lab(3);
  Margins m;
  m.a_gap = std::min(r1.a, r0.a) - std::max(g1.a, g0.a);
  m.red_b_gap = r1.b - r0.b;
  m.green_b_gap = g0.b - g1.b;
  m.a_spread = std::max(std::abs(r1.a - r0.a), std::abs(g1.a - g0.a));
  m.min_red_a = std::min(r1.a, r0.a);
  m.max_green_a = std::max(g1.a, g0.a);
  for (const ShadeReading& s : shades) m.noise_a = std::max(m.noise_a, s.pixel_noise_a);
  m.l_gap_white = white_l - std::max(g1.L, g0.L);
  m.red_decision = m.red_b_gap / std::max(1.0, CellSpread(shades[0], shades[1]));
  m.green_decision = m.green_b_gap / std::max(1.0, CellSpread(shades[2], shades[3]));
  return m;
}

Margins Worst(const Margins& a, const Margins& b) {
  Margins m;
  m.a_gap = std::min(a.a_gap, b.a_gap);
  m.red_b_gap = std::min(a.red_b_gap, b.red_b_gap);
  m.green_b_gap = std::min(a.green_b_gap, b.green_b_gap);
  m.a_spread = std::max(a.a_spread, b.a_spread);
  m.min_red_a = std::min(a.min_red_a, b.min_red_a);
  m.max_green_a = std::max(a.max_green_a, b.max_green_a);
  m.noise_a = std::max(a.noise_a, b.noise_a);
  m.l_gap_white = std::min(a.l_gap_white, b.l_gap_white);
  m.red_decision = std::min(a.red_decision, b.red_decision);
  m.green_decision = std::min(a.green_decision, b.green_decision);
  return m;
}

}  // namespace chromatag
