#include "chromatag/families/family.h"

#include <apriltag/apriltag.h>
#include <apriltag/tag16h5.h>
#include <apriltag/tag36h11.h>

#include <algorithm>
#include <bitset>
#include <cassert>
#include <mutex>

namespace chromatag {
namespace {

struct AprilTagSource {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

constexpr AprilTagSource kSources[] = {
    {"16h5", tag16h5_create, tag16h5_destroy},
    {"36h11", tag36h11_create, tag36h11_destroy},
};

std::string ShortName(const std::string& name) {
  return name.rfind("tag", 0) == 0 ? name.substr(3) : name;
}

// Translates libapriltag's bit order (bit i at bit_x[i], bit_y[i], counted
// from the black border, most significant first) into ours (row-major over the
// payload grid, most significant first).
Code ToPayloadCode(const apriltag_family_t& family, uint64_t apriltag_code, int d) {
  Code code = 0;
  const int n = static_cast<int>(family.nbits);
  for (int i = 0; i < n; ++i) {
    if ((apriltag_code >> (n - 1 - i)) & 1u) {
      const int row = static_cast<int>(family.bit_y[i]) - 1;
      const int col = static_cast<int>(family.bit_x[i]) - 1;
      code |= Code{1} << (n - 1 - (row * d + col));
    }
  }
  return code;
}

}  // namespace

int HammingDistance(Code a, Code b) { return static_cast<int>(std::bitset<64>(a ^ b).count()); }

std::string FormatIdRanges(const std::vector<int>& ids) {
  std::string out;
  for (size_t i = 0; i < ids.size();) {
    size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    out += (i ? ", " : "") + std::to_string(ids[i]);
    if (j > i) out += "-" + std::to_string(ids[j]);
    i = j + 1;
  }
  return out;
}

namespace {

// Why a code would print one shade only of red or of green (all its red
// cells, or all its green cells, the same bit); empty when it prints both.
std::string WhyOneShade(const TagFamily& family, Code code) {
  const int d = family.payload_width();
  int ones[2] = {0, 0};
  int cells[2] = {0, 0};
  for (int row = 0; row < d; ++row) {
    for (int col = 0; col < d; ++col) {
      const int color = family.CellColorAt(row, col) == CellColor::kRed ? 0 : 1;
      ++cells[color];
      ones[color] += family.Bit(code, row, col) ? 1 : 0;
    }
  }
  std::string reason;
  const char* names[2] = {"red", "green"};
  for (int color = 0; color < 2; ++color) {
    if (ones[color] == 0 || ones[color] == cells[color]) {
      if (!reason.empty()) reason += "; ";
      reason += std::string(names[color]) + " cells are all bit " + (ones[color] == 0 ? "0" : "1") +
                " (one shade, cannot be split)";
    }
  }
  return reason;
}

// The minimum distance over all relative rotations of the kept codes.
int MinDistanceOverRotations(const TagFamily& family, const std::vector<int>& kept) {
  int min_distance = family.num_bits();
  for (size_t i = 0; i < kept.size(); ++i) {
    const Code a = family.CodeOf(kept[i]);
    for (int turns = 1; turns < 4; ++turns) {
      min_distance = std::min(min_distance, HammingDistance(a, family.Rotate(a, turns)));
    }
    for (size_t j = i + 1; j < kept.size(); ++j) {
      const Code b = family.CodeOf(kept[j]);
      for (int turns = 0; turns < 4; ++turns) {
        min_distance = std::min(min_distance, HammingDistance(a, family.Rotate(b, turns)));
      }
    }
  }
  return min_distance;
}

}  // namespace

const std::vector<std::string>& TagFamily::Names() {
  static const std::vector<std::string> names = {"16h5", "36h11"};
  return names;
}

std::shared_ptr<const TagFamily> TagFamily::Load(const std::string& name, std::string* error) {
  const std::string short_name = ShortName(name);
  const AprilTagSource* source = nullptr;
  for (const auto& candidate : kSources) {
    if (short_name == candidate.name) source = &candidate;
  }
  if (source == nullptr) {
    if (error) *error = "unknown tag family '" + name + "' (valid: 16h5, 36h11)";
    return nullptr;
  }

  // Families are immutable once built; build each once per process.
  static std::mutex mutex;
  static std::shared_ptr<const TagFamily> cache[std::size(kSources)];
  std::lock_guard<std::mutex> lock(mutex);
  auto& cached = cache[source - kSources];
  if (cached) return cached;

  apriltag_family_t* april = source->create();
  std::shared_ptr<TagFamily> family(new TagFamily());
  family->name_ = source->name;
  family->payload_width_ = april->width_at_border - 2;
  family->apriltag_min_hamming_ = static_cast<int>(april->h);
  const int d = family->payload_width_;
  assert(static_cast<int>(april->nbits) == d * d);
  for (uint32_t id = 0; id < april->ncodes; ++id) {
    family->codes_.push_back(ToPayloadCode(*april, april->codes[id], d));
  }
  source->destroy(april);

  // Spec section 4: both shades of red and both shades of green.
  for (int id = 0; id < family->num_apriltag_ids(); ++id) {
    const std::string reason = WhyOneShade(*family, family->codes_[id]);
    if (reason.empty()) {
      family->kept_ids_.push_back(id);
    } else {
      family->rejected_.push_back({id, reason});
    }
  }
  family->min_hamming_ = MinDistanceOverRotations(*family, family->kept_ids_);
  cached = family;
  return cached;
}

CellColor TagFamily::CellColorAt(int row, int col) const {
  const int last = payload_width_ - 1;
  const bool outer = row == 0 || col == 0 || row == last || col == last;
  return outer ? CellColor::kGreen : CellColor::kRed;
}

int TagFamily::num_red_cells() const { return (payload_width_ - 2) * (payload_width_ - 2); }

int TagFamily::num_green_cells() const { return num_bits() - num_red_cells(); }

bool TagFamily::IsValidId(int id, std::string* why) const {
  if (id < 0 || id >= num_apriltag_ids()) {
    if (why) {
      *why = "ID " + std::to_string(id) + " is outside " + name_ + " (IDs 0-" +
             std::to_string(num_apriltag_ids() - 1) + ")";
    }
    return false;
  }
  for (const auto& rejected : rejected_) {
    if (rejected.id == id) {
      if (why) *why = name_ + " ID " + std::to_string(id) + " is rejected: " + rejected.reason;
      return false;
    }
  }
  return true;
}

Code TagFamily::CodeOf(int id) const {
  assert(id >= 0 && id < num_apriltag_ids());
  return codes_[id];
}

bool TagFamily::Bit(Code code, int row, int col) const {
  const int n = num_bits();
  return (code >> (n - 1 - (row * payload_width_ + col))) & 1u;
}

Code TagFamily::Rotate(Code code, int quarter_turns) const {
  const int d = payload_width_;
  const int n = num_bits();
  quarter_turns = ((quarter_turns % 4) + 4) % 4;
  for (int turn = 0; turn < quarter_turns; ++turn) {
    // Clockwise: the cell at (row, col) moves to (col, d - 1 - row).
    Code rotated = 0;
    for (int row = 0; row < d; ++row) {
      for (int col = 0; col < d; ++col) {
        if (Bit(code, row, col)) {
          const int new_row = col;
          const int new_col = d - 1 - row;
          rotated |= Code{1} << (n - 1 - (new_row * d + new_col));
        }
      }
    }
    code = rotated;
  }
  return code;
}

}  // namespace chromatag
