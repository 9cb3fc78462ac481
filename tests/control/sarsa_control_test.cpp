// SARSA(lambda) control: its reward, observation and action pieces against hand-computed
// values, the protocol of the first meta-generations, and learning on a synthetic bandit.
#include "qdmeta/control/sarsa_control.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <set>

#include "../expect_input_error.hpp"

namespace qdmeta {
namespace {

Eigen::MatrixXd samples(Rng& rng, int dimension = 3, int count = 4) {
  Eigen::MatrixXd s(dimension, count);
  for (Eigen::Index k = 0; k < s.size(); ++k) s.data()[k] = rng.normal();
  return s;
}

TEST(SarsaControl, RewardIsTheClippedRelativeImprovementPerEvaluation) {
  SarsaControl c{SarsaParams{}};
  // (110 - 100) / 100 / 20,000 x 30,000 = 0.15.
  EXPECT_NEAR(c.reward(110, 100, 20'000), 0.15, 1e-12);
  // Negative best: relative to |f_last|. (-50 - -100) / 100 / 1,000 x 30,000 = 15 -> clipped to 10.
  EXPECT_EQ(c.reward(-50, -100, 1'000), 10.0);
  EXPECT_EQ(c.reward(90, 100, 20'000), 0.0);  // no improvement: clipped at 0
  EXPECT_EQ(c.reward(5, 0, 20'000), 10.0);    // from zero: the largest reward
  EXPECT_EQ(c.reward(0, 0, 20'000), 0.0);
  EXPECT_THROW(c.reward(1, 0, 0), Error);
}

TEST(SarsaControl, DiversityIsTheSumOfSquaredPairwiseDistances) {
  Rng rng(1);
  const Eigen::MatrixXd s = samples(rng, 5, 7);
  // Independent identity: sum_{i<j} |x_i - x_j|^2 = n sum |x_i|^2 - |sum x_i|^2.
  const double expected = 7.0 * s.colwise().squaredNorm().sum() - s.rowwise().sum().squaredNorm();
  EXPECT_NEAR(SarsaControl::sample_diversity(s), expected, 1e-9 * expected);
  Eigen::MatrixXd two(2, 2);
  two << 0, 3, 0, 4;  // points (0,0) and (3,4)
  EXPECT_DOUBLE_EQ(SarsaControl::sample_diversity(two), 25.0);
}

TEST(SarsaControl, FiveIntervalsCoverOneToTenGenerations) {
  SarsaControl c{SarsaParams{}};
  // Width 1.8: [1, 2.8), [2.8, 4.6), [4.6, 6.4), [6.4, 8.2), [8.2, 10), each drawn and rounded.
  const std::array<std::pair<int, int>, 5> expected{{{1, 3}, {3, 5}, {5, 6}, {6, 8}, {8, 10}}};
  for (int a = 0; a < 5; ++a) EXPECT_EQ(c.action_range(a), expected[static_cast<std::size_t>(a)]) << a;
  // Over many meta-generations every G in 1..10 is used and none outside it.
  SarsaParams p;
  p.epsilon = 1.0;  // act at random
  SarsaControl random(p);
  std::set<int> seen;
  Rng rng(2);
  for (int t = 0; t < 2000; ++t) {
    const int g = random.choose_generations(samples(rng), rng);
    const auto [lo, hi] = random.action_range(random.last_action());
    EXPECT_GE(g, lo);
    EXPECT_LE(g, hi);
    seen.insert(g);
    random.observe(std::vector<double>{1.0 + t, 0.5}, 1000);
  }
  EXPECT_EQ(seen, (std::set<int>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10}));
}

TEST(SarsaControl, FirstStepsFollowTheProtocol) {
  SarsaControl c{SarsaParams{}};
  Rng rng(3);
  EXPECT_THROW(c.observe(std::vector<double>{1.0}, 10), Error);  // observe before choosing
  c.choose_generations(samples(rng), rng);
  c.observe(std::vector<double>{3.0, 1.0, 2.0}, 1000);
  EXPECT_EQ(c.last_reward(), 0.0);  // no previous best
  EXPECT_EQ(c.stagnation(), 0);
  // No transition is recorded for the first meta-generation (it had no observation).
  c.choose_generations(samples(rng), rng);
  EXPECT_TRUE(c.tree().node(0).transitions.empty());
  c.observe(std::vector<double>{2.0, 2.5}, 1000);  // best 2.5 < 3: stagnation
  EXPECT_EQ(c.last_reward(), 0.0);
  EXPECT_EQ(c.stagnation(), 1);
  c.choose_generations(samples(rng), rng);
  ASSERT_EQ(c.tree().node(0).transitions.size(), 1u);
  // The stored observation is the one made at the second meta-generation: best 3, mean 2,
  // population SD sqrt(2/3), stagnation 0, reward 0.
  const auto& o = c.tree().node(0).transitions[0].observation;
  EXPECT_EQ(o[kObsBest], 3.0);
  EXPECT_EQ(o[kObsMean], 2.0);
  EXPECT_NEAR(o[kObsSd], std::sqrt(2.0 / 3.0), 1e-15);
  EXPECT_EQ(o[kObsStagnation], 0.0);
  EXPECT_EQ(o[kObsReward], 0.0);
  c.observe(std::vector<double>{5.0}, 1000);  // 2.5 -> 5: relative 1, / 1000 x 30,000 -> clipped 10
  EXPECT_EQ(c.last_reward(), 10.0);
  EXPECT_EQ(c.stagnation(), 0);
}

// A bandit behind the controller's interface: the best meta-fitness grows by a factor that
// depends only on the interval chosen. SARSA must come to prefer the best interval.
// How often each interval is chosen in the second half of `steps` meta-generations.
std::array<int, 5> late_choices(std::uint64_t seed, int steps) {
  const std::array<double, 5> gain{0.0, 0.02, 0.05, 0.20, 0.05};
  SarsaParams p;
  p.reward_scale = 1000.0;  // with 1,000 evaluations a step, the reward equals the gain
  SarsaControl c(p);
  Rng rng(seed);
  double best = 1.0;
  std::array<int, 5> count{};
  for (int t = 0; t < steps; ++t) {
    c.choose_generations(samples(rng), rng);
    if (t >= steps / 2) ++count[static_cast<std::size_t>(c.last_action())];
    best *= 1.0 + gain[static_cast<std::size_t>(c.last_action())];
    c.observe(std::vector<double>{best, best / 2}, 1000);
  }
  return count;
}

TEST(SarsaControl, LearnsTheBestActionOfASyntheticBandit) {
  // Acting at random would choose interval 3 a fifth of the time; epsilon 0.1 caps it at 0.92.
  // The observation (which includes the growing best) splits the state space into ~25 leaves,
  // each inheriting its parent's Q-values, so learning continues across splits.
  for (std::uint64_t seed : {1, 2, 3, 4}) {
    const auto count = late_choices(seed, 1000);
    EXPECT_EQ(std::max_element(count.begin(), count.end()) - count.begin(), 3) << "seed " << seed;
    EXPECT_GT(count[3], 250) << "seed " << seed;  // of 500
  }
}

TEST(SarsaControl, SameStreamsSameChoices) {
  std::vector<int> runs[2];
  for (auto& choices : runs) {
    SarsaControl c{SarsaParams{}};
    Rng rng(9);
    double best = 1.0;
    for (int t = 0; t < 300; ++t) {
      choices.push_back(c.choose_generations(samples(rng), rng));
      best += rng.uniform() - 0.3;
      c.observe(std::vector<double>{best, best - 1}, 2000);
    }
    choices.push_back(static_cast<int>(c.states()));
  }
  EXPECT_EQ(runs[0], runs[1]);
}

TEST(SarsaControl, RejectsBadParameters) {
  SarsaParams p;
  p.max_generations = 0;
  EXPECT_INPUT_ERROR(SarsaControl{p}, "control.max_generations = 0 is out of range: must be in [1, 1000000]");
  p = SarsaParams{};
  p.epsilon = 1.5;
  EXPECT_INPUT_ERROR(SarsaControl{p}, "control.epsilon = 1.5 is out of range: must be in [0, 1]");
}

}  // namespace
}  // namespace qdmeta
