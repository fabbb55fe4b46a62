#include "chromatag/families/audit.h"

#include <algorithm>
#include <random>

namespace chromatag {
namespace {

int64_t Binomial(int n, int k) {
  int64_t result = 1;
  for (int i = 1; i <= k; ++i) result = result * (n - k + i) / i;
  return result;
}

void Record(const CodeDecoder& decoder, Code observed, int id, int rotation, FlipStats* stats) {
  ++stats->trials;
  CodeMatch match;
  if (!decoder.Decode(observed, &match)) {
    ++stats->rejected;
  } else if (match.id == id && match.rotation == rotation) {
    ++stats->correct;
  } else {
    ++stats->wrong_id;
  }
}

// Every pattern of exactly `flips` bits among `n`, applied to `code`.
template <typename Visit>
void ForEachPattern(Code code, int n, int flips, int first_bit, const Visit& visit) {
  if (flips == 0) {
    visit(code);
    return;
  }
  for (int bit = first_bit; bit <= n - flips; ++bit) {
    ForEachPattern(code ^ (Code{1} << bit), n, flips - 1, bit + 1, visit);
  }
}

}  // namespace

bool FamilyAudit::DecodingIsSafe() const {
  for (const auto& stats : flips) {
    if (stats.flips <= radius && stats.correct != stats.trials) return false;
  }
  return true;
}

namespace {

// Every pair of kept codes at its closest rotation, and each code against
// its own rotations; the pairs' distances counted in *histogram.
std::vector<CodePair> RotatedPairs(const TagFamily& family, std::vector<int64_t>* histogram) {
  const auto& ids = family.kept_ids();
  const int n = family.num_bits();
  std::vector<CodePair> pairs;
  for (size_t i = 0; i < ids.size(); ++i) {
    const Code a = family.CodeOf(ids[i]);
    for (int turns = 1; turns < 4; ++turns) {
      pairs.push_back({ids[i], ids[i], turns, HammingDistance(a, family.Rotate(a, turns))});
    }
    for (size_t j = i + 1; j < ids.size(); ++j) {
      CodePair closest{ids[i], ids[j], 0, n + 1};
      for (int turns = 0; turns < 4; ++turns) {
        const int d = HammingDistance(a, family.Rotate(family.CodeOf(ids[j]), turns));
        if (d < closest.distance) closest = {ids[i], ids[j], turns, d};
      }
      ++(*histogram)[closest.distance];
      pairs.push_back(closest);
    }
  }
  return pairs;
}

// What the decoder makes of every kept code, in every rotation, with
// `flips` bits flipped: every pattern when there are few enough, else
// random ones drawn from `rng`.
FlipStats DecodeWithFlips(const CodeDecoder& decoder, int flips, const AuditOptions& options,
                          std::mt19937_64& rng) {
  const TagFamily& family = decoder.family();
  const auto& ids = family.kept_ids();
  const int n = family.num_bits();
  FlipStats stats;
  stats.flips = flips;
  const int64_t patterns = Binomial(n, flips) * static_cast<int64_t>(ids.size()) * 4;
  stats.exhaustive = patterns <= options.max_exhaustive_patterns;
  if (stats.exhaustive) {
    for (int id : ids) {
      for (int rotation = 0; rotation < 4; ++rotation) {
        const Code code = family.Rotate(family.CodeOf(id), rotation);
        ForEachPattern(code, n, flips, 0,
                       [&](Code observed) { Record(decoder, observed, id, rotation, &stats); });
      }
    }
    return stats;
  }
  std::vector<int> bits(n);
  for (int t = 0; t < options.trials_per_flip_count; ++t) {
    const int id = ids[rng() % ids.size()];
    const int rotation = static_cast<int>(rng() % 4);
    Code observed = family.Rotate(family.CodeOf(id), rotation);
    for (int b = 0; b < n; ++b) bits[b] = b;
    for (int k = 0; k < flips; ++k) {  // A random set of distinct bits.
      std::swap(bits[k], bits[k + rng() % (n - k)]);
      observed ^= Code{1} << bits[k];
    }
    Record(decoder, observed, id, rotation, &stats);
  }
  return stats;
}

}  // namespace

FamilyAudit AuditFamily(const CodeDecoder& decoder, const AuditOptions& options) {
  const TagFamily& family = decoder.family();
  FamilyAudit audit;
  audit.num_codes = static_cast<int>(family.kept_ids().size());
  audit.min_distance = family.min_hamming();
  audit.radius = decoder.radius();
  audit.histogram.assign(family.num_bits() + 1, 0);
  std::vector<CodePair> pairs = RotatedPairs(family, &audit.histogram);
  const size_t listed = std::min(pairs.size(), static_cast<size_t>(options.max_pairs_listed));
  std::partial_sort(pairs.begin(), pairs.begin() + listed, pairs.end(),
                    [](const CodePair& x, const CodePair& y) {
                      return std::tie(x.distance, x.id_a, x.id_b, x.rotation) <
                             std::tie(y.distance, y.id_a, y.id_b, y.rotation);
                    });
  audit.closest_pairs.assign(pairs.begin(), pairs.begin() + listed);

  std::mt19937_64 rng(options.seed);
  for (int flips = 0; flips <= audit.min_distance; ++flips)
    audit.flips.push_back(DecodeWithFlips(decoder, flips, options, rng));
  return audit;
}

}  // namespace chromatag
