// Tag families: the AprilTag 16h5 and 36h11 codes as ChromaTags.
//
// Spec sections 1, 2 and 4. A ChromaTag of family F shows the payload of
// AprilTag F in a d x d grid of coloured cells (d = 4 for 16h5, 6 for 36h11):
// the inner (d-2) x (d-2) cells are red, the outer payload ring green. A code
// is kept only if its red cells hold both bit values and its green cells hold
// both bit values, since decoding splits each colour at its own midpoint.
// IDs are AprilTag's; a rejected ID is simply not valid.
#ifndef CHROMATAG_FAMILIES_FAMILY_H_
#define CHROMATAG_FAMILIES_FAMILY_H_

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace chromatag {

// A payload code in this project's own bit order: the d x d payload grid read
// row-major from the top-left cell of the upright tag, most significant bit
// first. 16h5 ID 0 is 0x231b (spec section 2). A 1 bit is a cell where the
// AprilTag is white: the red-1 or green-1 shade.
using Code = uint64_t;

// Which colour a payload cell is printed in.
enum class CellColor { kRed, kGreen };

struct RejectedId {
  int id = 0;
  std::string reason;  // For example "red cells are all bit 0 (one shade)".
};

class TagFamily {
 public:
  // The families this project supports, by their short names.
  static const std::vector<std::string>& Names();  // {"16h5", "36h11"}

  // Loads a family from libapriltag. Accepts "16h5" or "tag16h5" (and the same
  // for 36h11). Returns nullptr and sets *error (if given) for any other name.
  static std::shared_ptr<const TagFamily> Load(const std::string& name,
                                               std::string* error = nullptr);

  const std::string& name() const { return name_; }  // "16h5"
  // Payload width d (4 or 6) and the number of payload bits, d * d.
  int payload_width() const { return payload_width_; }
  int num_bits() const { return payload_width_ * payload_width_; }
  // Cells along the side of the black square, d + 2: the tag size spans these.
  int black_square_cells() const { return payload_width_ + 2; }
  // AprilTag's nominal minimum Hamming distance of the whole family (5, 11).
  int apriltag_min_hamming() const { return apriltag_min_hamming_; }

  CellColor CellColorAt(int row, int col) const;
  int num_red_cells() const;
  int num_green_cells() const;

  // Every AprilTag ID of the family: 0 .. num_apriltag_ids() - 1.
  int num_apriltag_ids() const { return static_cast<int>(codes_.size()); }
  const std::vector<int>& kept_ids() const { return kept_ids_; }
  const std::vector<RejectedId>& rejected_ids() const { return rejected_; }

  // True if `id` is a ChromaTag of this family. Otherwise, if `why` is given,
  // says why not (out of range, or rejected and for what reason).
  bool IsValidId(int id, std::string* why = nullptr) const;

  // The payload code of any AprilTag ID, kept or not. Requires
  // 0 <= id < num_apriltag_ids().
  Code CodeOf(int id) const;

  // Bit of the payload cell (row, col) of `code`, rows and columns from the top
  // left of the upright tag.
  bool Bit(Code code, int row, int col) const;

  // The code as seen after turning the printed tag `quarter_turns` times by 90
  // degrees clockwise, read row-major again.
  Code Rotate(Code code, int quarter_turns) const;

  // Minimum Hamming distance between any two kept codes in any relative
  // rotation, including a code against its own rotations (which would make
  // the orientation ambiguous).
  int min_hamming() const { return min_hamming_; }

  // The largest decoding radius r with 2 r < min_hamming(): no observed code
  // can then be within r of two codes or two rotations.
  int max_safe_radius() const { return (min_hamming_ - 1) / 2; }

 private:
  TagFamily() = default;

  std::string name_;
  int payload_width_ = 0;
  int apriltag_min_hamming_ = 0;
  std::vector<Code> codes_;  // By AprilTag ID.
  std::vector<int> kept_ids_;
  std::vector<RejectedId> rejected_;
  int min_hamming_ = 0;
};

// Number of differing bits.
int HammingDistance(Code a, Code b);

// "0-4, 6-9, 11" for sorted IDs.
std::string FormatIdRanges(const std::vector<int>& ids);

}  // namespace chromatag

#endif  // CHROMATAG_FAMILIES_FAMILY_H_
