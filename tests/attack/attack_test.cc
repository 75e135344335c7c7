// The attack suite as tests (label `attack`): every case against every
// program it applies to, each on a fresh process over loopback, with small
// volumes. Each asserts that the program is still running, that nothing
// got through, and that a legitimate client is served afterwards.
// tests/bench/attack runs the same cases with large volumes and prints the
// table quoted in the README.
#include <gtest/gtest.h>

#include <cctype>

#include "tests/attack/attacks.h"

namespace troupe::attack {
namespace {

struct Case {
  const Attack* attack;
  TargetKind target;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.attack->name << " on " << target_name(c.target);
}

std::vector<Case> all_cases() {
  std::vector<Case> cases;
  for (const Attack& a : attacks()) {
    for (TargetKind k : a.targets) cases.push_back({&a, k});
  }
  return cases;
}

std::string test_name(const ::testing::TestParamInfo<Case>& info) {
  std::string name = std::string(info.param.attack->name) + " on " + target_name(info.param.target);
  for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
}

class AttackTest : public ::testing::TestWithParam<Case> {};

TEST_P(AttackTest, SurvivesLetsNothingInAndServesAfterwards) {
  const Case& c = GetParam();
  std::string error;
  const Outcome out = run_attack(*c.attack, c.target, 1, error);
  ASSERT_TRUE(error.empty()) << error;
  EXPECT_GT(out.volume, 0u);
  EXPECT_TRUE(out.survived) << target_name(c.target) << " did not survive " << c.attack->name;
  EXPECT_EQ(out.let_in, 0u) << "first: " << out.first_let_in;
  EXPECT_TRUE(out.served) << out.why_not_served;
}

INSTANTIATE_TEST_SUITE_P(Attack, AttackTest, ::testing::ValuesIn(all_cases()), test_name);

}  // namespace
}  // namespace troupe::attack
