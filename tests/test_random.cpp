// The per-point generator of RANSAC (src/random.h, internal): skipping draws
// lands where drawing them would, which detect_texture relies on when it
// draws hypotheses ahead in batches and keeps only the tries it made.
#include <gtest/gtest.h>

#include <cstdint>

#include "../src/random.h"

namespace detexture {
namespace {

TEST(SplitMix64, SkipLandsWhereDrawingWould) {
  for (const std::uint64_t draws : {0ull, 1ull, 3ull, 24ull, 1000ull}) {
    SplitMix64 drawn(7, 42), skipped(7, 42);
    for (std::uint64_t d = 0; d < draws; ++d) drawn.next();
    skipped.skip(draws);
    for (int d = 0; d < 4; ++d) EXPECT_EQ(drawn.next(), skipped.next()) << draws << " draws";
  }
}

TEST(SplitMix64, StreamsDifferAndRepeat) {
  SplitMix64 a(1, 0), b(1, 1), again(1, 0);
  const std::uint64_t first = a.next();
  EXPECT_NE(first, b.next());
  EXPECT_EQ(first, again.next());
}

TEST(SplitMix64, BelowStaysInRange) {
  SplitMix64 rng(3, 5);
  for (const std::uint32_t n : {1u, 2u, 3u, 17u, 1000u}) {
    bool hit_top = false;
    for (int d = 0; d < 4000; ++d) {
      const std::uint32_t v = rng.below(n);
      ASSERT_LT(v, n);
      hit_top |= v == n - 1;
    }
    EXPECT_TRUE(hit_top) << "never drew " << n - 1;
  }
}

}  // namespace
}  // namespace detexture
