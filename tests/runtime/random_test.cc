// The one random generator gives the same numbers for the same seed on every
// platform: the values below were computed once and are pinned. bits() and
// uniform() are integer arithmetic, so they must match exactly; gaussian()
// goes through the C library's log and cos, correct to the last bit or two.
#include "runtime/random.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace troupe {
namespace {

TEST(Random, PinnedValuesForASeed) {
  Random r(42);
  EXPECT_EQ(r.bits(Random::stream(1, 2, 3), 0), 8506190899025204672ull);
  EXPECT_EQ(r.bits(Random::stream(1, 2, 3), 7), 6975561888573853540ull);
  EXPECT_EQ(r.uniform(Random::stream(5), 9), 0.14407298112641787);
  EXPECT_NEAR(r.gaussian(Random::stream(5), 9), -0.73962227285261184, 1e-15);
}

TEST(Random, ValueDependsOnlyOnSeedStreamAndCounter) {
  Random a(7), b(7), c(8);
  const uint64_t s = Random::stream(2, 10, 3);
  // Drawn in another order, the same (stream, counter) gives the same value.
  std::vector<double> forward, backward;
  for (uint64_t i = 0; i < 16; ++i) forward.push_back(a.uniform(s, i));
  for (uint64_t i = 16; i-- > 0;) backward.push_back(b.uniform(s, i));
  std::reverse(backward.begin(), backward.end());
  EXPECT_EQ(forward, backward);
  EXPECT_NE(a.bits(s, 0), c.bits(s, 0));
  EXPECT_NE(a.bits(Random::stream(2, 10, 3), 0), a.bits(Random::stream(2, 10, 4), 0));
}

TEST(RandomSequence, PinnedAndRepeatable) {
  RandomSequence s(7);
  EXPECT_EQ(s(), 13225839796362995591ull);
  EXPECT_EQ(s.uniform(), 0.52434594167793136);
  EXPECT_NEAR(s.gaussian(), 0.79059056585432941, 1e-15);
  s.seed(7);
  EXPECT_EQ(s(), 13225839796362995591ull);
}

TEST(RandomSequence, Moments) {
  RandomSequence s(3);
  const int n = 200000;
  double sum = 0, sum2 = 0, usum = 0;
  for (int i = 0; i < n; ++i) {
    double g = s.gaussian(2.0);
    sum += g;
    sum2 += g * g;
    usum += s.uniform(-1, 3);
  }
  EXPECT_NEAR(sum / n, 0.0, 0.03);
  EXPECT_NEAR(sum2 / n, 4.0, 0.06);
  EXPECT_NEAR(usum / n, 1.0, 0.02);
  EXPECT_EQ(s.gaussian(0.0), 0.0);
  EXPECT_FALSE(s.chance(0.0));
}

}  // namespace
}  // namespace troupe
