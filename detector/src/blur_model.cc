// The blur model (blur_model.h).
#include "blur_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

namespace chromatag::internal {
namespace {

constexpr int kMaxBlurGrid = 10;  // Payloads of up to 8 x 8 cells (36h11 has 6).
using GridShades = std::array<int, kMaxBlurGrid * kMaxBlurGrid>;

// The shade `pattern` gives each cell of the grid (d + 2 across, the black
// ring included): 0 red-0, 1 red-1, 2 green-0, 3 green-1, 4 black; with
// `merge_reds` both reds are 0. Returns the black ring's mean shade value.
double ShadesOfGrid(const TagFamily& family, Code pattern, const PayloadGrid& grid, bool merge_reds,
                    GridShades* shade) {
  const int d = family.payload_width(), w = d + 2;
  shade->fill(4);
  double black = 0;
  int ring = 0;
  for (int row = -1; row <= d; ++row) {
    for (int col = -1; col <= d; ++col) {
      const int i = (row + 1) * w + col + 1;
      if (row < 0 || col < 0 || row == d || col == d) {
        black += grid[i].shade;
        ++ring;
        continue;
      }
      const bool bit = (pattern >> (d * d - 1 - (row * d + col))) & 1u;
      const bool red = family.CellColorAt(row, col) == CellColor::kRed;
      (*shade)[i] = red ? (bit && !merge_reds ? 1 : 0) : (bit ? 3 : 2);
    }
  }
  black /= ring;
  return black;
}

// The blur model's equations for one pattern, in the share k. Cell j's
// coefficients of the four shades' levels are (1 - 4k) e_j + k n_j (e_j its
// own shade, n_j its neighbours' shades counted, c_j its neighbours in the
// black ring) and its value y_j - k black c_j; summed over the cells, the
// normal equations are polynomials in k:
//   ata(k) = (1 - 4k)^2 own + (1 - 4k) k cross + k^2 around,
//   atb(k) = (1 - 4k) (own_y - k black own_c) + k (around_y - k black around_c),
//   yy(k) = yy - 2 k black y_c + k^2 black^2 cc.
struct PatternEquations {
  // EquationsOf sets every field of the first n cells.
  struct Cell {
    int own;
    cv::Vec4d around;
    double ring, value;
  };
  std::array<Cell, (kMaxBlurGrid - 2) * (kMaxBlurGrid - 2)> cells;
  int n = 0;
  cv::Matx44d own = cv::Matx44d::zeros(), cross = cv::Matx44d::zeros(),
              around = cv::Matx44d::zeros();
  cv::Vec4d own_y, around_y, own_c, around_c;
  double yy = 0, y_c = 0, cc = 0, black = 0;

  cv::Matx44d Ata(double k) const {
    return (1 - 4 * k) * (1 - 4 * k) * own + (1 - 4 * k) * k * cross + k * k * around;
  }
  cv::Vec4d Atb(double k) const {
    const double kb = k * black;
    return (1 - 4 * k) * (own_y - kb * own_c) + k * (around_y - kb * around_c);
  }
  double Yy(double k) const {
    const double kb = k * black;
    return yy - 2 * kb * y_c + kb * kb * cc;
  }
  // Cell j's misfit at share k with the shades' levels `level`.
  double Misfit(int j, double k, const cv::Vec4d& level) const {
    const Cell& c = cells[j];
    return (1 - 4 * k) * level[c.own] + k * c.around.dot(level) - (c.value - k * black * c.ring);
  }
};

// Fills *eq for `pattern` (ShadesOfGrid's shades; with `merge_reds` both reds
// are red-0).
void EquationsOf(const TagFamily& family, Code pattern, const PayloadGrid& grid, bool merge_reds,
                 PatternEquations* eq) {
  const int d = family.payload_width(), w = d + 2;
  GridShades shade;
  eq->n = 0;
  eq->own = eq->cross = eq->around = cv::Matx44d::zeros();
  eq->own_y = eq->around_y = eq->own_c = eq->around_c = cv::Vec4d(0, 0, 0, 0);
  eq->yy = eq->y_c = eq->cc = 0;
  eq->black = ShadesOfGrid(family, pattern, grid, merge_reds, &shade);
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      const int i = (row + 1) * w + col + 1;
      PatternEquations::Cell& cell = eq->cells[eq->n++];
      cell.own = shade[i];
      cell.around = cv::Vec4d(0, 0, 0, 0);
      cell.ring = 0;
      for (int neighbour : {i - 1, i + 1, i - w, i + w}) {
        if (shade[neighbour] == 4)
          ++cell.ring;
        else
          cell.around[shade[neighbour]] += 1;
      }
      cell.value = grid[i].shade;
      cv::Vec4d e(0, 0, 0, 0);
      e[cell.own] = 1;
      const double y = cell.value, c = cell.ring;
      eq->own += e * e.t();
      eq->cross += e * cell.around.t() + cell.around * e.t();
      eq->around += cell.around * cell.around.t();
      eq->own_y += y * e;
      eq->around_y += y * cell.around;
      eq->own_c += c * e;
      eq->around_c += c * cell.around;
      eq->yy += y * y;
      eq->y_c += y * c;
      eq->cc += c * c;
    }
  }
}

// Adds to *best what the four shades' levels `level` make of the cells at
// share k: the worst cell's and the root mean square misfit over the
// smaller gap between a colour's two shades (without the reds' gap with
// `merge_reds`), and the misfit in shade units. A share whose levels put a
// colour's shades out of their order adds only the last.
void KeepShareFit(const PatternEquations& eq, double k, const cv::Vec4d& level, bool merge_reds,
                  BlurFit* best) {
  double worst = 0, sse = 0;
  for (int j = 0; j < eq.n; ++j) {
    const double r = eq.Misfit(j, k, level);
    worst = std::max(worst, std::abs(r));
    sse += r * r;
  }
  const int n = eq.n;
  best->abs_rms = std::min(best->abs_rms, std::sqrt(sse / n));
  // Red-1 lies above red-0, green-1 below green-0 (spec section 3).
  const double red_gap = merge_reds ? std::numeric_limits<double>::infinity() : level[1] - level[0];
  const double gap = std::min(red_gap, level[2] - level[3]);
  if (!(gap > 0)) return;
  best->worst = std::min(best->worst, worst / gap);
  if (std::sqrt(sse / n) / gap < best->rms) {
    best->rms = std::sqrt(sse / n) / gap;
    best->gap_balance = gap / std::max(level[1] - level[0], level[2] - level[3]);
  }
}

}  // namespace

BlurFit FitBlurModel(const TagFamily& family, Code pattern, const PayloadGrid& grid,
                     bool merge_reds) {
  if (family.payload_width() + 2 > kMaxBlurGrid) return {};
  PatternEquations eq;
  EquationsOf(family, pattern, grid, merge_reds, &eq);
  BlurFit best;
  for (float share : kBlurShares) {
    if (share > grid.max_blur_share + kBlurShares[1]) break;
    const double k = share;
    cv::Matx44d ata = eq.Ata(k);
    if (merge_reds) ata(1, 1) = 1.0;  // Red-1's level, unused, solves to 0.
    // Singular (a shade missing from the pattern): zero levels, no gap.
    const cv::Vec4d level = ata.solve(eq.Atb(k), cv::DECOMP_CHOLESKY);
    KeepShareFit(eq, k, level, merge_reds, &best);
  }
  return best;
}

double OrderedMisfit(const TagFamily& family, Code pattern, const PayloadGrid& grid, double bound) {
  if (family.payload_width() + 2 > kMaxBlurGrid) return std::numeric_limits<double>::infinity();
  PatternEquations eq;
  EquationsOf(family, pattern, grid, /*merge_reds=*/false, &eq);
  // The four shades' levels as 4, 3 (a colour merged) or 2 unknowns: the
  // merge's first columns; the unused ones are pinned to zero.
  static const cv::Matx44d kMerge[4] = {
      cv::Matx44d::eye(),
      {1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0},   // The reds as one.
      {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0},   // The greens as one.
      {1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0}};  // Both.
  static const int kUnknowns[4] = {4, 3, 3, 2};
  double best = std::numeric_limits<double>::infinity();
  for (float share : kBlurShares) {
    if (share > grid.max_blur_share + kBlurShares[1]) break;
    const double k = share;
    const cv::Matx44d ata = eq.Ata(k);
    const cv::Vec4d atb = eq.Atb(k);
    const double yy = eq.Yy(k);
    for (int v = 0; v < 4; ++v) {
      const cv::Matx44d& m = kMerge[v];
      cv::Matx44d reduced = m.t() * ata * m;
      cv::Vec4d x = m.t() * atb;
      for (int u = kUnknowns[v]; u < 4; ++u) {
        for (int c = 0; c < 4; ++c) reduced(u, c) = reduced(c, u) = 0;
        reduced(u, u) = 1;
        x[u] = 0;
      }
      // Singular (a shade missing from the pattern): that fit is skipped.
      if (!cv::Cholesky(reduced.val, 4 * sizeof(double), 4, x.val, sizeof(double), 1)) continue;
      const cv::Vec4d level = m * x;
      const double sse = yy - 2 * level.dot(atb) + level.dot(ata * level);
      if (std::isnan(sse)) continue;
      const bool in_order = level[1] >= level[0] - 1e-9 && level[2] >= level[3] - 1e-9;
      if (in_order) {
        best = std::min(best, std::max(0.0, sse));
        if (v == 0) break;  // The unconstrained fit in order is the share's optimum.
      } else if (v == 0 && !(sse < bound)) {
        best = std::min(best, std::max(0.0, sse));  // The bounded fits lie above it.
        break;
      }
    }
  }
  return best;
}

}  // namespace chromatag::internal
