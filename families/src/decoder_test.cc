#include "chromatag/families/decoder.h"

#include <gtest/gtest.h>

#include <random>

namespace chromatag {
namespace {

std::shared_ptr<const TagFamily> Family(const std::string& name) { return TagFamily::Load(name); }

// Brute force: the nearest kept code over all rotations.
CodeMatch Nearest(const TagFamily& family, Code observed) {
  CodeMatch best;
  best.hamming = 1000;
  for (int id : family.kept_ids()) {
    for (int rotation = 0; rotation < 4; ++rotation) {
      const int distance = HammingDistance(observed, family.Rotate(family.CodeOf(id), rotation));
      if (distance < best.hamming) best = {id, rotation, distance};
    }
  }
  return best;
}

TEST(CodeDecoderTest, DecodesEveryCodeRotationAndErrorPatternOf16h5) {
  auto family = Family("16h5");
  const int radius = family->max_safe_radius();
  std::string error;
  auto decoder = CodeDecoder::Create(family, radius, &error);
  ASSERT_TRUE(decoder) << error;
  const int n = family->num_bits();
  int checked = 0;
  for (int id : family->kept_ids()) {
    for (int rotation = 0; rotation < 4; ++rotation) {
      const Code code = family->Rotate(family->CodeOf(id), rotation);
      // All patterns of up to `radius` flips (radius <= 2 here).
      for (int i = -1; i < n; ++i) {
        for (int j = i; j < n; ++j) {
          Code observed = code;
          int flips = 0;
          if (i >= 0) observed ^= Code{1} << i, ++flips;
          if (j > i) observed ^= Code{1} << j, ++flips;
          if (flips > radius || (i < 0 && j >= 0)) continue;
          CodeMatch match;
          ASSERT_TRUE(decoder->Decode(observed, &match));
          EXPECT_EQ(match.id, id);
          EXPECT_EQ(match.rotation, rotation);
          EXPECT_EQ(match.hamming, flips);
          ++checked;
        }
      }
    }
  }
  EXPECT_EQ(checked, 28 * 4 * (1 + 16 + 120));
}

TEST(CodeDecoderTest, AgreesWithBruteForceOnEvery16BitPattern) {
  // Decodes exactly the patterns within the radius of some code, and those to
  // the nearest one; everything farther is refused.
  auto family = Family("16h5");
  auto decoder = CodeDecoder::Create(family, CodeDecoder::DefaultRadius(*family));
  ASSERT_TRUE(decoder);
  int decoded = 0;
  for (Code observed = 0; observed < (Code{1} << 16); ++observed) {
    const CodeMatch nearest = Nearest(*family, observed);
    CodeMatch match;
    const bool found = decoder->Decode(observed, &match);
    ASSERT_EQ(found, nearest.hamming <= decoder->radius()) << observed;
    if (found) {
      EXPECT_EQ(match.id, nearest.id);
      EXPECT_EQ(match.rotation, nearest.rotation);
      EXPECT_EQ(match.hamming, nearest.hamming);
      ++decoded;
    }
  }
  EXPECT_EQ(decoded, 28 * 4 * (1 + 16 + 120));
}

TEST(CodeDecoderTest, DecodesARandomSampleOf36h11WithErrors) {
  auto family = Family("36h11");
  std::string error;
  auto decoder = CodeDecoder::Create(family, 2, &error);
  ASSERT_TRUE(decoder) << error;
  std::mt19937_64 rng(36);
  std::uniform_int_distribution<int> pick_id(0, static_cast<int>(family->kept_ids().size()) - 1);
  std::uniform_int_distribution<int> pick_bit(0, family->num_bits() - 1);
  for (int trial = 0; trial < 20000; ++trial) {
    const int id = family->kept_ids()[pick_id(rng)];
    const int rotation = trial % 4;
    Code observed = family->Rotate(family->CodeOf(id), rotation);
    const int flips = trial % 3;
    int first = -1;
    for (int k = 0; k < flips; ++k) {
      int bit = pick_bit(rng);
      while (bit == first) bit = pick_bit(rng);
      first = bit;
      observed ^= Code{1} << bit;
    }
    CodeMatch match;
    ASSERT_TRUE(decoder->Decode(observed, &match)) << id;
    EXPECT_EQ(match.id, id);
    EXPECT_EQ(match.rotation, rotation);
    EXPECT_EQ(match.hamming, flips);
  }
}

TEST(CodeDecoderTest, RefusesRandom36BitPatternsFarFromEveryCode) {
  auto family = Family("36h11");
  auto decoder = CodeDecoder::Create(family, 2);
  ASSERT_TRUE(decoder);
  std::mt19937_64 rng(11);
  int refused = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Code observed = rng() & ((Code{1} << 36) - 1);
    const CodeMatch nearest = Nearest(*family, observed);
    CodeMatch match;
    const bool found = decoder->Decode(observed, &match);
    ASSERT_EQ(found, nearest.hamming <= 2);
    if (!found) ++refused;
    // Also three flips from a real code: farther than the radius.
    const int id = family->kept_ids()[trial % family->kept_ids().size()];
    const Code three_off = family->CodeOf(id) ^ Code { 0b10101 };
    EXPECT_FALSE(decoder->Decode(three_off, &match) && match.id == id);
  }
  EXPECT_GT(refused, 1900);
}

TEST(CodeDecoderTest, RefusesUnsafeOrOversizedRadius) {
  auto f16 = Family("16h5");
  std::string error;
  EXPECT_FALSE(CodeDecoder::Create(f16, f16->max_safe_radius() + 1, &error));
  EXPECT_NE(error.find("unsafe for 16h5"), std::string::npos) << error;
  EXPECT_FALSE(CodeDecoder::Create(f16, -1, &error));
  auto f36 = Family("36h11");
  EXPECT_FALSE(CodeDecoder::Create(f36, f36->max_safe_radius() + 1, &error));
  EXPECT_NE(error.find("must be at most 5"), std::string::npos) << error;
}

TEST(CodeDecoderTest, EverySafeRadiusOf36h11DecodesItsWorstCaseAndNoFarther) {
  // Multi-index hashing must find codes with exactly `radius` errors spread
  // over every block, for each radius it accepts.
  auto family = Family("36h11");
  std::mt19937_64 rng(5);
  for (int radius = 0; radius <= family->max_safe_radius(); ++radius) {
    std::string error;
    auto decoder = CodeDecoder::Create(family, radius, &error);
    ASSERT_TRUE(decoder) << error;
    EXPECT_LT(decoder->memory_bytes(), 1u << 20);
    for (int trial = 0; trial < 2000; ++trial) {
      const int id = family->kept_ids()[rng() % family->kept_ids().size()];
      const int rotation = static_cast<int>(rng() % 4);
      const Code code = family->Rotate(family->CodeOf(id), rotation);
      Code observed = code;
      while (HammingDistance(observed, code) < radius) observed ^= Code{1} << (rng() % 36);
      CodeMatch match;
      ASSERT_TRUE(decoder->Decode(observed, &match)) << "radius " << radius;
      EXPECT_EQ(match.id, id);
      EXPECT_EQ(match.rotation, rotation);
      EXPECT_EQ(match.hamming, radius);
      // One more flip puts it out of reach of this code (and, being within
      // min_hamming - radius - 1 of no other, of any).
      Code farther = observed;
      while (HammingDistance(farther, code) <= radius) farther ^= Code{1} << (rng() % 36);
      const bool found = decoder->Decode(farther, &match);
      EXPECT_TRUE(!found || match.id != id || match.rotation != rotation);
      EXPECT_EQ(found, Nearest(*family, farther).hamming <= radius);
    }
  }
}

}  // namespace
}  // namespace chromatag
