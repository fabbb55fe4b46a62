// Constant-time lookup from an observed payload code to (ID, rotation,
// Hamming distance), built once per family and radius.
//
// Small families (up to 20 bits, so 16h5) use a direct table with one entry
// per possible observation (256 KiB for 16h5). Larger ones use multi-index
// hashing: the bits are cut into k >= radius + 1 blocks, and every rotated
// code is filed under each of its k block values. An observation within the
// radius of a code matches it exactly in at least one block (pigeonhole), so
// looking in k buckets and checking the few codes there by popcount finds it.
// For 36h11 at radius 2 that is 3 buckets of 4096 and about 100 KiB in all,
// where a table of every neighbour (AprilTag's approach) would hold 1.6
// million entries and tens of megabytes.
#ifndef CHROMATAG_FAMILIES_DECODER_H_
#define CHROMATAG_FAMILIES_DECODER_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "chromatag/families/family.h"

namespace chromatag {

struct CodeMatch {
  int id = -1;
  // The observed code equals the tag's code turned `rotation` quarter turns
  // clockwise (TagFamily::Rotate), up to `hamming` flipped bits. To read the
  // tag upright, turn the observation back by `rotation` quarter turns.
  int rotation = 0;
  int hamming = 0;
};

class CodeDecoder {
 public:
  // The default radius: 2, as AprilTag's default, but never more than the
  // family's safe radius.
  static int DefaultRadius(const TagFamily& family);

  // Builds the table. Refuses (nullptr, *error set) a radius below 0 or one
  // with 2 r >= family.min_hamming(): two codes could then claim one
  // observation.
  static std::unique_ptr<CodeDecoder> Create(std::shared_ptr<const TagFamily> family, int radius,
                                             std::string* error = nullptr);

  // Looks `observed` up. Returns false if it is farther than radius() from
  // every kept code in every rotation.
  bool Decode(Code observed, CodeMatch* match) const;

  const TagFamily& family() const { return *family_; }
  int radius() const { return radius_; }
  size_t memory_bytes() const;

 private:
  CodeDecoder() = default;
  void BuildDirect();
  void BuildMultiIndex();

  static constexpr uint32_t kNoEntry = ~uint32_t{0};

  // One rotated code and its packed (id, rotation).
  struct Entry {
    Code code;
    uint32_t value;
  };
  // The bits [shift, shift + width) of a code, and its buckets: entries of
  // bucket v are entries[offsets[v] .. offsets[v + 1]).
  struct Block {
    int shift = 0;
    int width = 0;
    std::vector<uint32_t> offsets;
    std::vector<Entry> entries;
  };

  std::shared_ptr<const TagFamily> family_;
  int radius_ = 0;
  std::vector<uint32_t> direct_;  // Indexed by the observed code.
  std::vector<Block> blocks_;
};

}  // namespace chromatag

#endif  // CHROMATAG_FAMILIES_DECODER_H_
