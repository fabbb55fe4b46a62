#include "chromatag/families/decoder.h"

#include <algorithm>
#include <cassert>

namespace chromatag {
namespace {

constexpr int kDirectTableMaxBits = 20;
constexpr int kMaxBlockBits = 16;

// Value layout: id in bits 0-15, rotation in 16-17, hamming in 18-23.
uint32_t Pack(int id, int rotation, int hamming) {
  return static_cast<uint32_t>(id) | static_cast<uint32_t>(rotation) << 16 |
         static_cast<uint32_t>(hamming) << 18;
}

CodeMatch Unpack(uint32_t value) {
  return {static_cast<int>(value & 0xffffu), static_cast<int>((value >> 16) & 3u),
          static_cast<int>((value >> 18) & 63u)};
}

// Calls visit(pattern, flips) for every code within `radius` bits of `code`.
template <typename Visit>
void ForEachNeighbour(Code code, int num_bits, int radius, int first_bit, int flips,
                      const Visit& visit) {
  visit(code, flips);
  if (flips == radius) return;
  for (int bit = first_bit; bit < num_bits; ++bit) {
    ForEachNeighbour(code ^ (Code{1} << bit), num_bits, radius, bit + 1, flips + 1, visit);
  }
}

}  // namespace

int CodeDecoder::DefaultRadius(const TagFamily& family) {
  return std::min(2, family.max_safe_radius());
}

std::unique_ptr<CodeDecoder> CodeDecoder::Create(std::shared_ptr<const TagFamily> family,
                                                 int radius, std::string* error) {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return nullptr;
  };
  if (!family) return fail("no tag family given");
  if (radius < 0) return fail("decoding radius must be 0 or more");
  if (radius > family->max_safe_radius()) {
    return fail("decoding radius " + std::to_string(radius) + " is unsafe for " + family->name() +
                ": its minimum Hamming distance over rotations is " +
                std::to_string(family->min_hamming()) + ", so the radius must be at most " +
                std::to_string(family->max_safe_radius()));
  }
  std::unique_ptr<CodeDecoder> decoder(new CodeDecoder());
  decoder->family_ = family;
  decoder->radius_ = radius;
  if (family->num_bits() <= kDirectTableMaxBits) {
    decoder->BuildDirect();
  } else {
    decoder->BuildMultiIndex();
  }
  return decoder;
}

void CodeDecoder::BuildDirect() {
  const int n = family_->num_bits();
  direct_.assign(size_t{1} << n, kNoEntry);
  for (int id : family_->kept_ids()) {
    for (int rotation = 0; rotation < 4; ++rotation) {
      const Code rotated = family_->Rotate(family_->CodeOf(id), rotation);
      ForEachNeighbour(rotated, n, radius_, 0, 0, [&](Code pattern, int flips) {
        // A safe radius gives every pattern one owner.
        assert(direct_[pattern] == kNoEntry);
        direct_[pattern] = Pack(id, rotation, flips);
      });
    }
  }
}

void CodeDecoder::BuildMultiIndex() {
  const int n = family_->num_bits();
  const int num_blocks = std::max(radius_ + 1, (n + kMaxBlockBits - 1) / kMaxBlockBits);
  std::vector<Entry> all;
  for (int id : family_->kept_ids()) {
    for (int rotation = 0; rotation < 4; ++rotation) {
      all.push_back({family_->Rotate(family_->CodeOf(id), rotation), Pack(id, rotation, 0)});
    }
  }
  int shift = 0;
  for (int b = 0; b < num_blocks; ++b) {
    Block block;
    block.shift = shift;
    block.width = n / num_blocks + (b < n % num_blocks ? 1 : 0);
    shift += block.width;
    const Code mask = (Code{1} << block.width) - 1;
    // Counting sort of the entries by their value in this block.
    block.offsets.assign((size_t{1} << block.width) + 1, 0);
    for (const Entry& entry : all) ++block.offsets[((entry.code >> block.shift) & mask) + 1];
    for (size_t v = 1; v < block.offsets.size(); ++v) block.offsets[v] += block.offsets[v - 1];
    block.entries.resize(all.size());
    std::vector<uint32_t> next(block.offsets.begin(), block.offsets.end() - 1);
    for (const Entry& entry : all)
      block.entries[next[(entry.code >> block.shift) & mask]++] = entry;
    blocks_.push_back(std::move(block));
  }
}

bool CodeDecoder::Decode(Code observed, CodeMatch* match) const {
  if (!direct_.empty()) {
    if (observed >= direct_.size() || direct_[observed] == kNoEntry) return false;
    *match = Unpack(direct_[observed]);
    return true;
  }
  for (const Block& block : blocks_) {
    const Code value = (observed >> block.shift) & ((Code{1} << block.width) - 1);
    for (uint32_t i = block.offsets[value]; i < block.offsets[value + 1]; ++i) {
      const Entry& entry = block.entries[i];
      const int distance = HammingDistance(observed, entry.code);
      // Within a safe radius there is at most one such code.
      if (distance <= radius_) {
        *match = Unpack(entry.value);
        match->hamming = distance;
        return true;
      }
    }
  }
  return false;
}

size_t CodeDecoder::memory_bytes() const {
  size_t bytes = direct_.size() * sizeof(uint32_t);
  for (const Block& block : blocks_) {
    bytes += block.offsets.size() * sizeof(uint32_t) + block.entries.size() * sizeof(Entry);
  }
  return bytes;
}

}  // namespace chromatag
