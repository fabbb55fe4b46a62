#include "chromatag/families/audit.h"

#include <gtest/gtest.h>

namespace chromatag {
namespace {

TEST(AuditTest, SixteenH5PairsAndFlipsAreAccountedFor) {
  auto family = TagFamily::Load("16h5");
  auto decoder = CodeDecoder::Create(family, 2);
  const FamilyAudit audit = AuditFamily(*decoder);
  EXPECT_EQ(audit.num_codes, 28);
  EXPECT_EQ(audit.min_distance, 5);
  int64_t pairs = 0;
  for (size_t d = 0; d < audit.histogram.size(); ++d) {
    pairs += audit.histogram[d];
    if (audit.histogram[d] > 0) {
      EXPECT_GE(static_cast<int>(d), audit.min_distance);
    }
  }
  EXPECT_EQ(pairs, 28 * 27 / 2);
  ASSERT_FALSE(audit.closest_pairs.empty());
  const CodePair& closest = audit.closest_pairs.front();
  EXPECT_EQ(closest.distance, 5);
  EXPECT_EQ(HammingDistance(family->CodeOf(closest.id_a),
                            family->Rotate(family->CodeOf(closest.id_b), closest.rotation)),
            5);
  // Within the radius every pattern decodes right; 16h5 is small enough to
  // enumerate every pattern up to its minimum distance.
  ASSERT_EQ(audit.flips.size(), 6u);
  EXPECT_TRUE(audit.DecodingIsSafe());
  for (const auto& stats : audit.flips) {
    EXPECT_TRUE(stats.exhaustive);
    EXPECT_EQ(stats.trials, stats.correct + stats.wrong_id + stats.rejected);
    if (stats.flips <= 2) {
      EXPECT_EQ(stats.correct, stats.trials);
    }
  }
  EXPECT_EQ(audit.flips[2].trials, 28 * 4 * 120);
  // Three flips can land within 2 of another code: the confusions it shows
  // are real and there are some, since the minimum distance is 5.
  EXPECT_GT(audit.flips[3].wrong_id, 0);
  EXPECT_EQ(audit.flips[3].correct, 0);
}

TEST(AuditTest, ThirtySixH11SamplesWhereItCannotEnumerate) {
  auto family = TagFamily::Load("36h11");
  auto decoder = CodeDecoder::Create(family, 2);
  AuditOptions options;
  options.trials_per_flip_count = 2000;
  const FamilyAudit audit = AuditFamily(*decoder, options);
  EXPECT_EQ(audit.min_distance, 11);
  EXPECT_TRUE(audit.flips[2].exhaustive);
  EXPECT_EQ(audit.flips[2].trials, 587 * 4 * 630);
  EXPECT_FALSE(audit.flips[6].exhaustive);
  EXPECT_EQ(audit.flips[6].trials, 2000);
  EXPECT_TRUE(audit.DecodingIsSafe());
  // Far from any code at 3 to 8 flips with d_min 11 and radius 2: nothing
  // can be confused before 9 flips.
  for (int flips = 3; flips <= 8; ++flips) EXPECT_EQ(audit.flips[flips].wrong_id, 0) << flips;
}

}  // namespace
}  // namespace chromatag
