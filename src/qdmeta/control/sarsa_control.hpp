#pragma once
// SARSA(lambda) control of G, the MAP-Elites generations per meta-generation (paper section
// "Dynamic parameter control", Karafotias et al. 2014; docs/specification.md, SARSA(lambda) control). Actions are
// intervals of [min, max] generations; the state is the leaf of a StateTree over a 6-D
// observation of meta-evolutionary progress; the reward is the relative improvement of the
// best meta-fitness per evaluation.
#include <optional>
#include <vector>

#include "qdmeta/control/controller.hpp"
#include "qdmeta/control/state_tree.hpp"
#include "qdmeta/core/params.hpp"

namespace qdmeta {

struct SarsaParams {
  // The config parameters read into this struct and checked by validate() (core/params.hpp); `actions` is StateTreeParams::kActions.
  static constexpr IntParam kMinGenerations{"control", "min_generations", 1, 1'000'000, "smallest G SARSA may choose"};
  static constexpr IntParam kMaxGenerations{"control", "max_generations", 1, 1'000'000, "largest G SARSA may choose"};
  static constexpr RealParam kEpsilon{"control", "epsilon", 0.0, 1.0, Open::kNone,
      "exploration rate of the epsilon-greedy policy"};
  static constexpr RealParam kGamma{"control", "gamma", 0.0, 1.0, Open::kNone, "discount"};
  static constexpr RealParam kAlpha{"control", "alpha", 0.0, 1.0, Open::kNone, "learning rate"};
  static constexpr RealParam kAlphaZeroReward{"control", "alpha_zero_reward", 0.0, 1.0, Open::kNone,
      "learning rate of a step whose reward is 0"};
  static constexpr RealParam kTraceDecay{"control", "trace_decay", 0.0, 1.0, Open::kNone,
      "lambda of SARSA(lambda) (replacing traces)"};
  static constexpr RealParam kTraceMin{"control", "trace_min", 0.0, 1.0, Open::kNone, "traces below this are dropped"};
  static constexpr RealParam kRewardScale{"control", "reward_scale", 0.0, kNoUpper, Open::kLower,
      "reward = relative best-meta-fitness improvement / evaluations x scale (Rastrigin 30,000, RHex "
      "24,096)"};
  static constexpr RealParam kRewardMax{"control", "reward_max", 0.0, kNoUpper, Open::kLower,
      "rewards are clipped to [0, reward_max]"};
  int actions = 5;                // interval actions splitting [min_generations, max_generations]
  int min_generations = 1;
  int max_generations = 10;
  double epsilon = 0.1;           // exploration rate of the epsilon-greedy policy
  double gamma = 0.8;             // discount
  double alpha = 0.9;             // learning rate
  double alpha_zero_reward = 0.2; // learning rate of a step whose reward is 0
  double trace_decay = 0.8;       // lambda of SARSA(lambda)
  double trace_min = 0.001;       // traces below this are dropped
  double reward_scale = 30'000;   // Rastrigin 30,000; RHex 24,096
  double reward_max = 10.0;       // rewards are clipped to [0, reward_max]
  StateTreeParams tree;           // its attributes and actions are set by SarsaControl
  void validate() const;
};

// The observation, in the order of docs/specification.md (SARSA(lambda) control).
enum ObservationAttribute : int {
  kObsBest = 0,      // best meta-fitness of the previous meta-generation
  kObsMean = 1,      // its mean
  kObsSd = 2,        // its population SD
  kObsDiversity = 3, // sum of squared pairwise distances of the new CMA-ES samples
  kObsStagnation = 4,// meta-generations since the best of a meta-generation last improved
  kObsReward = 5,    // the reward of the previous meta-generation
  kObservationSize = 6
};

class SarsaControl final : public GenerationController {
 public:
  explicit SarsaControl(SarsaParams params);  // throws InputError on bad parameters

  std::string name() const override { return "sarsa"; }
  int choose_generations(const Eigen::MatrixXd& samples, Rng& rng) override;
  void observe(std::span<const double> meta_fitness, std::int64_t evaluations) override;
  std::int64_t states() const override { return static_cast<std::int64_t>(tree_.leaf_count()); }
  void save(BinaryWriter& out) const override;
  void load(BinaryReader& in) override;

  // Inspection (tests, logs).
  const StateTree& tree() const { return tree_; }
  const SarsaParams& params() const { return params_; }
  int max_generations() const override { return params_.max_generations; }
  double last_reward() const { return reward_; }
  int stagnation() const { return stagnation_; }
  int last_action() const { return action_; }
  // The generations an action's interval allows: [lo, hi] after rounding.
  std::pair<int, int> action_range(int action) const;

  // Pure pieces, public for tests.
  static double sample_diversity(const Eigen::MatrixXd& samples);
  double reward(double best, double previous_best, std::int64_t evaluations) const;

 private:
  // Action `action`'s interval [lo, hi) of generations, before rounding.
  std::pair<double, double> interval(int action) const;
  int choose_action(int leaf, Rng& rng) const;
  int draw_generations(int action, Rng& rng) const;
  // The SARSA(lambda) update on <s, a, r, s', a'>, then the transition into s's leaf.
  void learn(int next_leaf, int next_action, Rng& rng);

  SarsaParams params_;
  StateTree tree_;
  // The previous step: its leaf, its observation (none at the first meta-generation), action.
  int leaf_ = 0;
  std::optional<std::vector<double>> observation_;
  int action_ = -1;
  // Statistics of the latest observed meta-generation.
  bool has_statistics_ = false;
  double best_ = 0.0, mean_ = 0.0, sd_ = 0.0;
  double reward_ = 0.0;
  int stagnation_ = 0;
};

}  // namespace qdmeta
