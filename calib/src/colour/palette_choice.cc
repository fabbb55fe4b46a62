// Choosing the calibrated palette (palette_choice.h).
#include "chromatag/calib/palette_choice.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

namespace chromatag {
namespace {

struct Option {
  Lab intended;
  int patch = -1;
  std::vector<Lab> measured;  // Per photo.
};

// One colour's options: its candidates and the sheet palette's two shades,
// each with its mean measured colour in every photo (none if any photo has
// no usable patch of it).
std::vector<Option> Options(const CalibSheetLayout& layout,
                            const std::vector<PhotoMeasurement>& photos, Shade candidate_tag,
                            Shade one, Shade zero, const PaletteChoiceOptions& o) {
  // Keyed by the sent RGB: the palette's repeats are one option.
  std::map<uint32_t, Option> by_rgb;
  std::map<uint32_t, std::vector<std::vector<Lab>>> readings;
  for (const Patch& patch : layout.patches) {
    const bool is_candidate = patch.kind == PatchKind::kCandidate && patch.shade == candidate_tag;
    const bool is_palette =
        patch.kind == PatchKind::kPalette && (patch.shade == one || patch.shade == zero);
    if (!is_candidate && !is_palette) continue;
    const uint32_t key = (patch.rgb.r << 16) | (patch.rgb.g << 8) | patch.rgb.b;
    if (!by_rgb.count(key)) {
      by_rgb[key] = Option{patch.lab, is_candidate ? patch.index : -1, {}};
      readings[key].resize(photos.size());
    }
    for (size_t p = 0; p < photos.size(); ++p) {
      const PatchMeasurement& m = photos[p].patches[patch.index];
      if (m.usable()) readings[key][p].push_back(m.lab);
    }
  }
  std::vector<Option> out;
  for (auto& [key, option] : by_rgb) {
    bool complete = true;
    for (size_t p = 0; p < photos.size() && complete; ++p) {
      const auto& labs = readings[key][p];
      if (labs.empty()) {
        complete = false;
        break;
      }
      Lab mean;
      for (const Lab& l : labs) {
        mean.L += l.L / labs.size();
        mean.a += l.a / labs.size();
        mean.b += l.b / labs.size();
      }
      // Far enough from black and from the paper in L*.
      double black_l = 0;
      int n = 0;
      for (const Patch& patch : layout.patches) {
        const PatchMeasurement& m = photos[p].patches[patch.index];
        if (patch.kind == PatchKind::kPalette && patch.shade == Shade::kBlack && m.usable()) {
          black_l += m.lab.L;
          ++n;
        }
      }
      black_l = n ? black_l / n : 0.0;
      if (mean.L < black_l + o.min_l_from_black_and_white ||
          mean.L > 100.0 - o.min_l_from_black_and_white)
        complete = false;
      option.measured.push_back(mean);
    }
    if (complete) out.push_back(option);
  }
  return out;
}

// A pair (bit-1 shade, bit-0 shade) of one colour, with what the search needs
// per photo.
struct Pair {
  int one = 0, zero = 0;
  double worst_b_gap = 0;
  double worst_a_spread = 0;
  std::vector<double> a_bound;  // Reds: the paler red's a*; greens: the redder green's a*.
};

// Bit 1 is the higher-b* red and the lower-b* green (spec section 3).
std::vector<Pair> Pairs(const std::vector<Option>& options, bool red, size_t photos,
                        const PaletteChoiceOptions& o) {
  std::vector<Pair> out;
  for (size_t i = 0; i < options.size(); ++i) {
    for (size_t j = 0; j < options.size(); ++j) {
      if (i == j) continue;
      const Option &one = options[i], &zero = options[j];
      const double file_gap =
          red ? one.intended.b - zero.intended.b : zero.intended.b - one.intended.b;
      if (file_gap < 6.0) continue;  // The palette file's required shade order.
      Pair pair{static_cast<int>(i), static_cast<int>(j), 1e300, 0, {}};
      for (size_t p = 0; p < photos; ++p) {
        const Lab &l1 = one.measured[p], &l0 = zero.measured[p];
        pair.worst_b_gap = std::min(pair.worst_b_gap, red ? l1.b - l0.b : l0.b - l1.b);
        pair.worst_a_spread = std::max(pair.worst_a_spread, std::abs(l1.a - l0.a));
        pair.a_bound.push_back(red ? std::min(l1.a, l0.a) : std::max(l1.a, l0.a));
      }
      if (pair.worst_b_gap > 0 && pair.worst_a_spread <= o.max_a_spread) out.push_back(pair);
    }
  }
  return out;
}

double Score(double a_gap, double red_b, double green_b, const PaletteChoiceOptions& o) {
  return std::min({a_gap / o.a_goal, red_b / o.b_goal, green_b / o.b_goal});
}

// The best set found by the search: its red pair, its green pair (none: nullptr) and a* gap.
struct BestSet {
  const Pair* red = nullptr;
  const Pair* green = nullptr;
  double a_gap = 0;
};

// Scores every red pair with every green pair; the best's score and spread go into *best.
BestSet SearchSets(const std::vector<Option>& reds, const std::vector<Option>& greens,
                   const std::vector<Pair>& red_pairs, const std::vector<Pair>& green_pairs,
                   size_t photos, const PaletteChoiceOptions& o, PaletteChoice* best) {
  BestSet set;
  best->score = -1e300;
  double best_total = -1e300;
  for (const Pair& r : red_pairs) {
    for (const Pair& g : green_pairs) {
      const double file_a_gap = std::min(reds[r.one].intended.a, reds[r.zero].intended.a) -
                                std::max(greens[g.one].intended.a, greens[g.zero].intended.a);
      if (file_a_gap < 25.0) continue;  // The palette file's required a* gap.
      double a_gap = 1e300;
      for (size_t p = 0; p < photos; ++p) a_gap = std::min(a_gap, r.a_bound[p] - g.a_bound[p]);
      const double score = Score(a_gap, r.worst_b_gap, g.worst_b_gap, o);
      ++best->combinations;
      // The smallest margin decides; among sets it ranks equal (common: one
      // colour's b* gap limits every set), the larger sum of all three, then
      // the smaller a* spread between shades.
      const double total = a_gap / o.a_goal + r.worst_b_gap / o.b_goal + g.worst_b_gap / o.b_goal;
      const double spread = std::max(r.worst_a_spread, g.worst_a_spread);
      const bool tie = std::abs(score - best->score) <= 1e-9;
      if (score > best->score + 1e-9 || (tie && total > best_total + 1e-9) ||
          (tie && std::abs(total - best_total) <= 1e-9 && spread < best->a_spread)) {
        best->score = score;
        best->a_spread = spread;
        best_total = total;
        set.red = &r;
        set.green = &g;
        set.a_gap = a_gap;
      }
    }
  }
  return set;
}

// Why no palette could be chosen.
std::string NoSetMessage(const PaletteChoiceOptions& o) {
  return "no set of printed reds and greens keeps the shades apart (b* order as in the "
         "file, a* within " +
         std::to_string(static_cast<int>(o.max_a_spread)) +
         " between shades, L* clear of black and white): this printer cannot print a "
         "ChromaTag palette from these candidates";
}

// Writes the chosen set's margins, shades and palette (named and described) into *best.
void FillChoice(const CalibSheetLayout& layout, size_t photos, const std::vector<Option>& reds,
                const std::vector<Option>& greens, const BestSet& set, PaletteChoice* best) {
  best->a_gap = set.a_gap;
  best->red_b_gap = set.red->worst_b_gap;
  best->green_b_gap = set.green->worst_b_gap;
  const Option* chosen[4] = {&reds[set.red->one], &reds[set.red->zero], &greens[set.green->one],
                             &greens[set.green->zero]};
  const Shade shades[4] = {Shade::kRed1, Shade::kRed0, Shade::kGreen1, Shade::kGreen0};
  best->palette = layout.palette;
  for (int k = 0; k < 4; ++k) {
    best->shades[k] = ChosenShade{chosen[k]->intended, chosen[k]->patch, chosen[k]->measured};
    best->palette[shades[k]] = chosen[k]->intended;
  }
  best->palette.name = "sheet-" + std::to_string(layout.sheet_id) + "-calibrated";
  char description[300];
  std::snprintf(description, sizeof(description),
                "Chosen by chromatag calibrate from sheet %d in %zu photo(s): worst-case printed "
                "a* gap %.1f, b* gaps %.1f (reds) and %.1f (greens)",
                layout.sheet_id, photos, best->a_gap, best->red_b_gap, best->green_b_gap);
  best->palette.description = description;
}

// The sheet's own palette, scored the same way, for comparison (0 if a shade has no reading).
double SheetPaletteScore(const CalibSheetLayout& layout, size_t photos,
                         const std::vector<Option>& reds, const std::vector<Option>& greens,
                         const PaletteChoiceOptions& o) {
  auto find = [](const std::vector<Option>& options, const Lab& lab) {
    for (size_t i = 0; i < options.size(); ++i) {
      if (options[i].patch < 0 && LabToSrgb8(options[i].intended) == LabToSrgb8(lab))
        return static_cast<int>(i);
    }
    return -1;
  };
  const int r1 = find(reds, layout.palette[Shade::kRed1]);
  const int r0 = find(reds, layout.palette[Shade::kRed0]);
  const int g1 = find(greens, layout.palette[Shade::kGreen1]);
  const int g0 = find(greens, layout.palette[Shade::kGreen0]);
  if (r1 < 0 || r0 < 0 || g1 < 0 || g0 < 0) return 0;
  double a_gap = 1e300, rb = 1e300, gb = 1e300;
  for (size_t p = 0; p < photos; ++p) {
    const Lab &l1 = reds[r1].measured[p], &l0 = reds[r0].measured[p];
    const Lab &m1 = greens[g1].measured[p], &m0 = greens[g0].measured[p];
    a_gap = std::min(a_gap, std::min(l1.a, l0.a) - std::max(m1.a, m0.a));
    rb = std::min(rb, l1.b - l0.b);
    gb = std::min(gb, m0.b - m1.b);
  }
  return Score(a_gap, rb, gb, o);
}

}  // namespace

bool PaletteChoiceOptions::IsValid(std::string* error) const {
  if (!(a_goal > 0 && b_goal > 0 && max_a_spread > 0 && min_l_from_black_and_white >= 0)) {
    if (error) *error = "palette choice: goals and max_a_spread must be positive";
    return false;
  }
  return true;
}

std::optional<PaletteChoice> ChoosePalette(const CalibSheetLayout& layout,
                                           const std::vector<PhotoMeasurement>& photos,
                                           const PaletteChoiceOptions& o, std::string* error) {
  if (!o.IsValid(error)) return std::nullopt;
  const std::vector<Option> reds =
      Options(layout, photos, Shade::kRed1, Shade::kRed1, Shade::kRed0, o);
  const std::vector<Option> greens =
      Options(layout, photos, Shade::kGreen1, Shade::kGreen1, Shade::kGreen0, o);
  const std::vector<Pair> red_pairs = Pairs(reds, true, photos.size(), o);
  const std::vector<Pair> green_pairs = Pairs(greens, false, photos.size(), o);

  PaletteChoice best;
  const BestSet set = SearchSets(reds, greens, red_pairs, green_pairs, photos.size(), o, &best);
  if (!set.red) {
    if (error) *error = NoSetMessage(o);
    return std::nullopt;
  }
  FillChoice(layout, photos.size(), reds, greens, set, &best);
  best.sheet_palette_score = SheetPaletteScore(layout, photos.size(), reds, greens, o);
  return best;
}

}  // namespace chromatag
