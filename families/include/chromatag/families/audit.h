// The family audit: how far apart the codes are, and what bit errors do to
// decoding. This is the inter-marker confusion study the paper's authors left
// as open work; `chromatag verify --family F --all` prints it.
#ifndef CHROMATAG_FAMILIES_AUDIT_H_
#define CHROMATAG_FAMILIES_AUDIT_H_

#include <cstdint>
#include <string>
#include <vector>

#include "chromatag/families/decoder.h"
#include "chromatag/families/family.h"

namespace chromatag {

struct AuditOptions {
  // Random bit-flip trials per number of flipped bits, where enumerating every
  // pattern would take longer. >= 1.
  int trials_per_flip_count = 20000;
  // Patterns are enumerated exhaustively when there are at most this many.
  int64_t max_exhaustive_patterns = 2'000'000;
  // How many of the closest pairs to list.
  int max_pairs_listed = 20;
  uint64_t seed = 1;
};

// Two kept codes, `b` turned `rotation` quarter turns, `distance` bits apart.
// id_a == id_b is a code against its own rotation.
struct CodePair {
  int id_a = 0;
  int id_b = 0;
  int rotation = 0;
  int distance = 0;
};

// What decoding a code with `flips` bits flipped gave.
struct FlipStats {
  int flips = 0;
  bool exhaustive = false;  // Every pattern, or a random sample.
  int64_t trials = 0;
  int64_t correct = 0;   // The right ID and rotation.
  int64_t wrong_id = 0;  // Another ID, or the right one turned wrong: a confusion.
  int64_t rejected = 0;  // No ID within the radius.
};

struct FamilyAudit {
  int num_codes = 0;
  int min_distance = 0;
  int radius = 0;
  // histogram[d]: unordered pairs of distinct kept codes whose distance,
  // minimised over relative rotations, is d.
  std::vector<int64_t> histogram;
  // Closest pairs first (pairs of distinct codes and self-rotations alike).
  std::vector<CodePair> closest_pairs;
  // flips = 0 .. min_distance.
  std::vector<FlipStats> flips;

  // True if no pattern within the radius decoded wrongly or not at all.
  bool DecodingIsSafe() const;
};

FamilyAudit AuditFamily(const CodeDecoder& decoder, const AuditOptions& options = {});

// The audit as JSON (one line; the "audit" of `chromatag verify --family F
// --all --json`): codes, min_distance, radius, distance_histogram,
// closest_pairs (id_a, id_b, rotation, distance), bit_flips (flips,
// exhaustive, trials, correct, wrong_id, rejected) and decoding_safe.
std::string FamilyAuditJson(const FamilyAudit& audit);

}  // namespace chromatag

#endif  // CHROMATAG_FAMILIES_AUDIT_H_
